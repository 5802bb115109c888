#include "field/empty_reach.h"

#include <algorithm>

namespace tessera {

namespace {

/// One chamfer pass over the grid in raster order `dir` (+1 forward, -1 backward): each empty
/// cell takes 1 + the least reach among the 13 neighbours already visited in that order.
void chamfer_pass(const std::int64_t nc[3], std::uint8_t* reach, int dir) {
  const std::int64_t nx = nc[0], ny = nc[1], nz = nc[2];
  const auto at = [&](std::int64_t x, std::int64_t y, std::int64_t z) -> int {
    if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) return kMaxEmptyReach;  // outside: empty
    return reach[(z * ny + y) * nx + x];
  };
  for (std::int64_t s = 0; s < nz; ++s) {
    const std::int64_t z = dir > 0 ? s : nz - 1 - s;
    for (std::int64_t r = 0; r < ny; ++r) {
      const std::int64_t y = dir > 0 ? r : ny - 1 - r;
      for (std::int64_t q = 0; q < nx; ++q) {
        const std::int64_t x = dir > 0 ? q : nx - 1 - q;
        std::uint8_t& c = reach[(z * ny + y) * nx + x];
        if (c == 0) continue;
        int m = c;
        // The visited half of the 26-neighbourhood: the previous slice (9), the previous row
        // of this slice (3) and the previous cell of this row (1), in the pass' direction.
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) m = std::min(m, at(x + dx, y + dy, z - dir) + 1);
        for (int dx = -1; dx <= 1; ++dx) m = std::min(m, at(x + dx, y - dir, z) + 1);
        m = std::min(m, at(x - dir, y, z) + 1);
        c = static_cast<std::uint8_t>(m);
      }
    }
  }
}

}  // namespace

void fill_empty_reach(const double* majorant, const std::int64_t nc[3], std::uint8_t* reach) {
  const std::int64_t n = nc[0] * nc[1] * nc[2];
  for (std::int64_t c = 0; c < n; ++c) reach[c] = majorant[c] > 0.0 ? 0 : kMaxEmptyReach;
  chamfer_pass(nc, reach, +1);
  chamfer_pass(nc, reach, -1);
}

}  // namespace tessera
