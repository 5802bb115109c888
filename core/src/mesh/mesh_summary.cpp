/// mesh_summary (mesh_summary.h): each element's range scattered over the macrocells its box meets.
#include "mesh/mesh_summary.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

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

std::shared_ptr<const FieldSummary> mesh_summary(const MeshTables& tables, int edge) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  const MacroGrid m = macro_grid(tables.geometry(), tables.dims(), edge);
  FieldSummary::Parts parts = empty_cells(m);
  for (std::size_t e = 0; e < tables.element_count(); ++e) fold_into_cells(parts, m, tables.box(e), tables.range(e));
  parts.nan = tables.nan_values();
  parts.elements = std::max<std::uint64_t>(1, tables.value_count());
  parts.vmin = tables.value_min();
  parts.vmax = tables.value_max();
  FieldLayout layout;
  layout.dtype = DType::Float64;
  for (int a = 0; a < 3; ++a) layout.dims[a] = tables.dims()[a];
  return FieldSummary::from_parts(std::move(parts), layout, edge);
}

}  // namespace tessera
