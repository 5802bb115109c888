#pragma once
// Per-domain coordinates for tests (tessera_domain coords, axes_from_domains): each domain's
// piece of a rectilinear axis, its real vertices and `ghosts` more on each side (values past
// the axis' ends extrapolated: the adapter ignores them), kept alive here.
#include <tessera/tessera.h>

#include <cstdint>
#include <deque>
#include <vector>

namespace tessera_test {

class AxisPieces {
 public:
  /// Gives every domain of `domains` its piece of axis `a` of `axis` (the global vertex
  /// coordinates; a domain's real vertices along a: field dims - ghosts, from its offset, and
  /// one more for cell data, whose n cells have n + 1 vertices).
  void give(std::vector<tessera_domain>& domains, int a, const std::vector<double>& axis, int ghosts = 1,
            bool cells = false) {
    for (tessera_domain& d : domains) {
      const tessera_field& f = d.fields[0];
      const std::int64_t real = f.dims[a] - f.ghosts_lo[a] - f.ghosts_hi[a];
      std::vector<double>& piece = m_pieces.emplace_back();
      const std::int64_t start = d.offset[a] - ghosts;
      const auto n = static_cast<std::int64_t>(axis.size());
      for (std::int64_t g = start; g < d.offset[a] + real + (cells ? 1 : 0) + ghosts; ++g)
        piece.push_back(g < 0    ? axis[0] - static_cast<double>(-g)
                        : g >= n ? axis[n - 1] + static_cast<double>(g - n + 1)
                                 : axis[static_cast<std::size_t>(g)]);
      d.coords[a] = piece.data();
      d.coords_start[a] = start;
      d.coords_count[a] = static_cast<std::int64_t>(piece.size());
    }
  }

 private:
  std::deque<std::vector<double>> m_pieces;
};

}  // namespace tessera_test
