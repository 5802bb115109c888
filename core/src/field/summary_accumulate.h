#pragma once
/// The per-vertex merge of FieldSummary::accumulate (field_summary.h), as a template over the
/// vertex loader, shared by a FieldView's summary and a vector's magnitude summary
/// (magnitude_field.h) so that both bin, canonicalise and count values by the same rules.
#include <tessera/field_summary.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::summary_detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr CellRange kEmpty{kInf, -kInf, false, false, false};

/// Macrocells along an axis of `dims` vertices with edge `edge` (at least one).
inline std::int64_t cells_along(std::int64_t dims, int edge) {
  return std::max<std::int64_t>(1, (dims - 1 + edge - 1) / edge);
}

/// Zeros as +0.0: min / max of -0.0 and +0.0 depend on the order, so that a summary combined
/// from parts in any order equals the one pass's, every zero is +0.0 in the ranges.
inline double canonical(double v) { return v == 0.0 ? 0.0 : v; }

inline void merge_value(CellRange& a, double v) {
  v = canonical(v);
  if (std::isnan(v)) a.nan = true;
  else if (v == kInf) a.pos_inf = true;
  else if (v == -kInf) a.neg_inf = true;
  else {
    a.lo = v < a.lo ? v : a.lo;
    a.hi = a.hi < v ? v : a.hi;
  }
}

/// The cells of one axis of `global` vertices that vertex g (0 <= g < global) is folded into:
/// the cell that owns it and, on an inner cell boundary, the cell whose +1 overlap holds it
/// (`prev`, else equal to `own`). The rule accumulate_values and the device summary share.
inline void vertex_cells(std::int64_t g, std::int64_t cells, int edge, std::int64_t& own, std::int64_t& prev) {
  own = std::min(g / edge, cells - 1);
  prev = g % edge == 0 && g > 0 && g / edge <= cells - 1 ? g / edge - 1 : own;
}

/// The cells [first, last] of one axis that a block of `dims` vertices at `offset` touches in
/// a field of `global` vertices with edge `edge` (vertex_cells over its vertices).
inline void cell_window(std::int64_t offset, std::int64_t dims, std::int64_t global, int edge, std::int64_t& first,
                        std::int64_t& last) {
  const std::int64_t cells = cells_along(global, edge);
  std::int64_t own = 0;
  vertex_cells(offset, cells, edge, own, first);
  std::int64_t prev = 0;
  vertex_cells(offset + dims - 1, cells, edge, last, prev);
}

/// Throws std::invalid_argument unless `parts` has the cells of a field of `global_dims`
/// with edge `edge` (and edge >= 1).
inline void check_parts(const FieldSummary::Parts& parts, const std::int64_t global_dims[3], int edge) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  std::int64_t n = 1;
  for (int a = 0; a < 3; ++a) n *= parts.cells[a];
  for (int a = 0; a < 3; ++a)
    if (parts.cells[a] != cells_along(global_dims[a], edge) || parts.lo.size() != static_cast<std::size_t>(n) ||
        parts.hi.size() != parts.lo.size() || parts.flags.size() != parts.lo.size())
      throw std::invalid_argument("summary parts of " + std::to_string(parts.cells[0]) + "x" +
                                  std::to_string(parts.cells[1]) + "x" + std::to_string(parts.cells[2]) +
                                  " cells do not fit the field with edge " + std::to_string(edge));
}

/// Throws std::invalid_argument unless a block of `dims` at `offset` lies inside `global_dims`.
inline void check_block_inside(const std::int64_t dims[3], const std::int64_t offset[3],
                               const std::int64_t global_dims[3]) {
  for (int a = 0; a < 3; ++a)
    if (offset[a] < 0 || offset[a] + dims[a] > global_dims[a])
      throw std::invalid_argument("block of " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" +
                                  std::to_string(dims[2]) + " at offset " + std::to_string(offset[0]) + "," +
                                  std::to_string(offset[1]) + "," + std::to_string(offset[2]) +
                                  " is not inside the field");
}

/// Merges the values load(i, j, k) of a block of `dims` at `offset` into `parts` (checked by
/// the caller): every vertex into the cell that owns it and, on an inner cell boundary, the
/// cell whose +1 overlap holds it; the NaN count and the finite min / max.
template <class Load>
void accumulate_values(FieldSummary::Parts& parts, const std::int64_t dims[3], const std::int64_t offset[3], int edge,
                       Load&& load) {
  std::vector<std::int64_t> own[3], prev[3];
  for (int a = 0; a < 3; ++a) {
    own[a].resize(static_cast<std::size_t>(dims[a]));
    prev[a].resize(static_cast<std::size_t>(dims[a]));
    for (std::int64_t v = 0; v < dims[a]; ++v)
      vertex_cells(offset[a] + v, parts.cells[a], edge, own[a][static_cast<std::size_t>(v)],
                   prev[a][static_cast<std::size_t>(v)]);
  }
  CellRange total = kEmpty;
  for (std::int64_t k = 0; k < dims[2]; ++k)
    for (std::int64_t j = 0; j < dims[1]; ++j)
      for (std::int64_t i = 0; i < dims[0]; ++i) {
        const double v = canonical(load(i, j, k));
        parts.nan += v != v;
        merge_value(total, v);
        const std::int64_t cx[2] = {own[0][i], prev[0][i]}, cy[2] = {own[1][j], prev[1][j]},
                           cz[2] = {own[2][k], prev[2][k]};
        for (int z = 0; z < (cz[1] != cz[0] ? 2 : 1); ++z)
          for (int y = 0; y < (cy[1] != cy[0] ? 2 : 1); ++y)
            for (int x = 0; x < (cx[1] != cx[0] ? 2 : 1); ++x) {
              const auto c = static_cast<std::size_t>((cz[z] * parts.cells[1] + cy[y]) * parts.cells[0] + cx[x]);
              if (v != v) parts.flags[c] |= 1;
              else if (v == kInf) parts.flags[c] |= 2;
              else if (v == -kInf) parts.flags[c] |= 4;
              else {
                parts.lo[c] = std::min(parts.lo[c], v);
                parts.hi[c] = std::max(parts.hi[c], v);
              }
            }
      }
  parts.vmin = std::min(parts.vmin, total.lo);
  parts.vmax = std::max(parts.vmax, total.hi);
}

}  // namespace tessera::summary_detail
