#include <tessera/tiles.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace tessera {
namespace {
std::uint64_t morton2(std::uint32_t x, std::uint32_t y) {
  std::uint64_t code = 0;
  for (int b = 0; b < 32; ++b) {
    code |= static_cast<std::uint64_t>((x >> b) & 1u) << (2 * b);
    code |= static_cast<std::uint64_t>((y >> b) & 1u) << (2 * b + 1);
  }
  return code;
}
}  // namespace

std::vector<Tile> make_tiles(int width, int height, int edge, TileOrder order) {
  if (edge < 0) throw std::invalid_argument("tile edge " + std::to_string(edge) + " must be >= 0");
  if (width < 1 || height < 1) throw std::invalid_argument("image must be at least 1x1");
  std::vector<Tile> tiles;
  if (edge == 0) {  // scanline: one tile per row
    for (int y = 0; y < height; ++y) tiles.push_back({0, y, width, y + 1});
    return tiles;
  }
  const int nx = (width + edge - 1) / edge, ny = (height + edge - 1) / edge;
  std::vector<std::pair<std::uint64_t, Tile>> keyed;
  for (int ty = 0; ty < ny; ++ty)
    for (int tx = 0; tx < nx; ++tx) {
      const Tile t{tx * edge, ty * edge, std::min(width, (tx + 1) * edge), std::min(height, (ty + 1) * edge)};
      const std::uint64_t key = order == TileOrder::Morton
                                    ? morton2(static_cast<std::uint32_t>(tx), static_cast<std::uint32_t>(ty))
                                    : static_cast<std::uint64_t>(ty) * nx + tx;
      keyed.emplace_back(key, t);
    }
  std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& k : keyed) tiles.push_back(k.second);
  return tiles;
}

}  // namespace tessera
