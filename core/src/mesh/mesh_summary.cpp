/// mesh_summary (mesh_summary.h): each element's range scattered over the macrocells its box meets.
#include "mesh/mesh_summary.h"

#include "mesh/macro_spans.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace tessera {

MacroGrid macro_grid(const VolumeGeometry& g, const std::int64_t* dims, int edge) {
  MacroGrid m;
  m.edge = edge;
  for (int a = 0; a < 3; ++a) {
    m.origin[a] = g.origin[a];
    m.spacing[a] = g.spacing[a];
    m.cells[a] = std::max<std::int64_t>(1, (dims[a] - 1 + edge - 1) / edge);
  }
  return m;
}

FieldSummary::Parts empty_cells(const MacroGrid& g) {
  FieldSummary::Parts parts;
  for (int a = 0; a < 3; ++a) parts.cells[a] = g.cells[a];
  const auto ncells = static_cast<std::size_t>(g.cells[0] * g.cells[1] * g.cells[2]);
  parts.lo.assign(ncells, INFINITY);
  parts.hi.assign(ncells, -INFINITY);
  parts.flags.assign(ncells, 0);
  return parts;
}

void fold_into_cells(FieldSummary::Parts& parts, const MacroGrid& g, const double* box, const ElementRange& r) {
  std::int64_t c0[3], c1[3];
  g.span(box, c0, c1);
  for (std::int64_t k = c0[2]; k <= c1[2]; ++k)
    for (std::int64_t j = c0[1]; j <= c1[1]; ++j)
      for (std::int64_t i = c0[0]; i <= c1[0]; ++i) {
        const auto c = static_cast<std::size_t>((k * g.cells[1] + j) * g.cells[0] + i);
        parts.lo[c] = std::min(parts.lo[c], r.lo);
        parts.hi[c] = std::max(parts.hi[c], r.hi);
        parts.flags[c] |= r.flags;
      }
}

namespace {

/// Cells of the input below which the fold stays on one thread.
constexpr std::size_t kParallelFold = 32768;

/// Folds range `r` into the macrocells of span `s` (MacroSpan: n[0] >= 1).
void fold_span(FieldSummary::Parts& parts, const MacroGrid& g, const MacroSpan& s, const ElementRange& r) {
  const auto nx = static_cast<std::size_t>(g.cells[0]), layer = nx * static_cast<std::size_t>(g.cells[1]);
  const auto first = static_cast<std::size_t>(s.first);
  for (std::uint32_t k = 0; k < s.n[2]; ++k)
    for (std::uint32_t j = 0; j < s.n[1]; ++j) {
      const std::size_t row = first + k * layer + j * nx;
      for (std::uint32_t i = 0; i < s.n[0]; ++i) {
        const std::size_t c = row + i;
        parts.lo[c] = std::min(parts.lo[c], r.lo);
        parts.hi[c] = std::max(parts.hi[c], r.hi);
        parts.flags[c] |= r.flags;
      }
    }
}

/// The input's cells [begin, end) (over all domains, MacroSpans::all's numbering) folded into
/// `parts`: each element of the layout's range from the current arrays, in input order.
void fold_cells(FieldSummary::Parts& parts, const MacroGrid& m, const MacroSpans& spans, const DomainAccess* domains,
                std::size_t begin, std::size_t end) {
  const std::span<const MacroSpan> all = spans.all();
  if (begin == end) return;
  std::size_t d = spans.domain_of(begin);
  for (std::size_t c = begin; c != end; ++c) {
    while (static_cast<std::size_t>(spans.offset(d + 1)) <= c) ++d;
    const MacroSpan& s = all[c];
    if (s.n[0] == 0) continue;  // not an element of the layout
    const MeshElementRef ref{static_cast<std::int64_t>(c) - spans.offset(d), static_cast<std::int32_t>(d)};
    fold_span(parts, m, s, element_range(domains, ref));
  }
}

/// The elements among the input's cells [begin, end) of `tables` folded into `parts`, in the
/// input's order (MacroSpans). Over the threads of the caller's arena when there are many
/// elements per macrocell: each thread folds a share into cells of its own, then the cells are
/// merged. Min, max and or of values without NaN or -0.0 (add_value) give the same bits in any
/// order, so the result is the serial fold's (and the canonical order's). The threads' copies
/// together hold at most a quarter as many cells as the range has input cells (about 4 bytes
/// per cell, whatever the thread count); a grid of more cells (a small macrocell edge, many
/// threads) would cost more in copies than the fold: one thread.
void fold_elements(FieldSummary::Parts& parts, const MacroGrid& m, const MeshTables& tables, const MacroSpans& spans,
                   std::size_t begin, std::size_t end) {
  const std::size_t n = end - begin;
  const std::size_t cells = parts.lo.size();
  const auto threads = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const DomainAccess* domains = tables.domains().data();
  if (n < kParallelFold || cells > n / 4 / threads) {
    fold_cells(parts, m, spans, domains, begin, end);
    return;
  }
  tbb::combinable<FieldSummary::Parts> mine([&] { return empty_cells(m); });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 8192), [&](const tbb::blocked_range<std::size_t>& r) {
    fold_cells(mine.local(), m, spans, domains, r.begin(), r.end());
  });
  mine.combine_each([&](const FieldSummary::Parts& p) {
    for (std::size_t c = 0; c < cells; ++c) {
      parts.lo[c] = std::min(parts.lo[c], p.lo[c]);
      parts.hi[c] = std::max(parts.hi[c], p.hi[c]);
      parts.flags[c] |= p.flags[c];
    }
  });
}

/// Share `share` of `shares` of n things: [n share / shares, n (share + 1) / shares).
std::pair<std::uint64_t, std::uint64_t> share_of(std::uint64_t n, int share, int shares) {
  const auto s = static_cast<unsigned __int128>(share), k = static_cast<unsigned __int128>(shares);
  return {static_cast<std::uint64_t>(n * s / k), static_cast<std::uint64_t>(n * (s + 1) / k)};
}

}  // namespace

FieldSummary::Parts mesh_summary_share(const MeshTables& tables, int edge, int share, int shares) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  if (shares < 1 || share < 0 || share >= shares)
    throw std::invalid_argument("mesh summary: share " + std::to_string(share) + " of " + std::to_string(shares) +
                                " (0 <= share < shares)");
  const MacroGrid m = macro_grid(tables.geometry(), tables.dims(), edge);
  FieldSummary::Parts parts = empty_cells(m);
  const std::shared_ptr<const MacroSpans> spans = tables.layout()->macro_spans(m);
  const auto [c0, c1] = share_of(spans->all().size(), share, shares);
  fold_elements(parts, m, tables, *spans, c0, c1);
  const auto [v0, v1] = share_of(tables.value_count(), share, shares);
  const MeshTables::ValueTotals t = tables.value_totals(v0, v1);
  parts.nan = t.nan;
  parts.elements = t.count;
  parts.vmin = t.lo;
  parts.vmax = t.hi;
  return parts;
}

std::shared_ptr<const FieldSummary> mesh_summary_of(FieldSummary::Parts&& parts, const MeshLayout& layout, int edge) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  const MacroGrid m = macro_grid(layout.geometry(), layout.dims(), edge);
  if (parts.lo.size() != static_cast<std::size_t>(m.cells[0] * m.cells[1] * m.cells[2]) ||
      parts.hi.size() != parts.lo.size() || parts.flags.size() != parts.lo.size())
    throw std::invalid_argument("mesh summary: the parts have " + std::to_string(parts.lo.size()) +
                                " macrocells, this mesh's grid with edge " + std::to_string(edge) + " has " +
                                std::to_string(m.cells[0] * m.cells[1] * m.cells[2]));
  parts.elements = std::max<std::uint64_t>(1, parts.elements);
  FieldLayout field;
  field.dtype = DType::Float64;
  for (int a = 0; a < 3; ++a) field.dims[a] = layout.dims()[a];
  return FieldSummary::from_parts(std::move(parts), field, edge);
}

std::shared_ptr<const FieldSummary> mesh_summary(const MeshTables& tables, int edge) {
  return mesh_summary_of(mesh_summary_share(tables, edge, 0, 1), *tables.layout(), edge);
}

}  // namespace tessera
