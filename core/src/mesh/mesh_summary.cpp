/// mesh_summary (mesh_summary.h): each element's range scattered over the macrocells its box meets.
#include "mesh/mesh_summary.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tessera {

std::shared_ptr<const FieldSummary> mesh_summary(const MeshTables& tables, int edge) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  const VolumeGeometry g = tables.geometry();
  FieldSummary::Parts parts;
  for (int a = 0; a < 3; ++a) parts.cells[a] = std::max<std::int64_t>(1, (tables.dims()[a] - 1 + edge - 1) / edge);
  const auto ncells = static_cast<std::size_t>(parts.cells[0] * parts.cells[1] * parts.cells[2]);
  parts.lo.assign(ncells, INFINITY);
  parts.hi.assign(ncells, -INFINITY);
  parts.flags.assign(ncells, 0);
  // The macrocell of world coordinate x along axis a, nudged by `pad` voxels
  const auto cell = [&](int a, double x, double pad) {
    const double p = (x - g.origin[a]) / g.spacing[a] + pad;
    const double q = std::floor(std::clamp(p, -1.0, 9e18) / edge);
    return std::clamp<std::int64_t>(static_cast<std::int64_t>(q), 0, parts.cells[a] - 1);
  };
  for (std::size_t e = 0; e < tables.element_count(); ++e) {
    const double* b = tables.box(e);
    const ElementRange& r = tables.range(e);
    std::int64_t c0[3], c1[3];
    for (int a = 0; a < 3; ++a) {
      c0[a] = cell(a, b[a], -1e-6);
      c1[a] = cell(a, b[3 + a], 1e-6);
    }
    for (std::int64_t k = c0[2]; k <= c1[2]; ++k)
      for (std::int64_t j = c0[1]; j <= c1[1]; ++j)
        for (std::int64_t i = c0[0]; i <= c1[0]; ++i) {
          const auto c = static_cast<std::size_t>((k * parts.cells[1] + j) * parts.cells[0] + i);
          parts.lo[c] = std::min(parts.lo[c], r.lo);
          parts.hi[c] = std::max(parts.hi[c], r.hi);
          parts.flags[c] |= r.flags;
        }
  }
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
