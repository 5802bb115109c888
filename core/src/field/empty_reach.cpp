#include "field/empty_reach.h"

#include <algorithm>

namespace tessera {

namespace {

/// One chamfer pass over the grid in raster order `dir` (+1 forward, -1 backward): each empty
/// cell takes 1 + the least reach among the 13 neighbours already visited in that order (the
/// previous slice's 9, the previous row's 3 and the previous cell). A neighbour outside the
/// grid counts as kMaxEmptyReach, so it never lowers a reach: interior cells read their
/// neighbours by offset, cells on the grid's faces through the bounds-checked `at`.
void chamfer_pass(const std::int64_t nc[3], std::uint8_t* reach, int dir) {
  const std::int64_t nx = nc[0], ny = nc[1], nz = nc[2];
  const std::int64_t sy = nx, sz = nx * ny;
  const auto at = [&](std::int64_t x, std::int64_t y, std::int64_t z) -> int {
    if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) return kMaxEmptyReach;  // outside: empty
    return reach[(z * ny + y) * nx + x];
  };
  for (std::int64_t s = 0; s < nz; ++s) {
    const std::int64_t z = dir > 0 ? s : nz - 1 - s;
    const bool has_slice = s > 0;  // the previous slice in the pass' direction lies in the grid
    for (std::int64_t r = 0; r < ny; ++r) {
      const std::int64_t y = dir > 0 ? r : ny - 1 - r;
      const bool inner_y = y > 0 && y < ny - 1;
      for (std::int64_t q = 0; q < nx; ++q) {
        const std::int64_t x = dir > 0 ? q : nx - 1 - q;
        const std::int64_t idx = (z * ny + y) * nx + x;
        if (reach[idx] == 0) continue;
        int m = reach[idx];
        if (inner_y && x > 0 && x < nx - 1) {
          if (has_slice) {
            const std::uint8_t* ps = reach + idx - dir * sz;
            for (std::int64_t dy = -sy; dy <= sy; dy += sy)
              for (std::int64_t dx = -1; dx <= 1; ++dx) m = std::min(m, ps[dy + dx] + 1);
          }
          const std::uint8_t* pr = reach + idx - dir * sy;
          for (std::int64_t dx = -1; dx <= 1; ++dx) m = std::min(m, pr[dx] + 1);
          m = std::min(m, reach[idx - dir] + 1);
        } else {
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) m = std::min(m, at(x + dx, y + dy, z - dir) + 1);
          for (int dx = -1; dx <= 1; ++dx) m = std::min(m, at(x + dx, y - dir, z) + 1);
          m = std::min(m, at(x - dir, y, z) + 1);
        }
        reach[idx] = static_cast<std::uint8_t>(m);
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
