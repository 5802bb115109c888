/// The host loops of mesh_device.h: one cell or value at a time with the device's per-item code.
#include "cuda/mesh_device.h"

#include <tessera/cuda_render.h>

#include "mesh/element_indices.h"
#include "mesh/mesh_checked_issuer.h"
#include "mesh/mesh_summary.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tessera::cuda {

MeshIndexFault mesh_index_fault_host(const Mesh& mesh) {
  MeshIndexFault f;
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const MeshDomain& md = mesh.domains[i];
    const DomainAccess a = DomainAccess::of(md);
    const std::int64_t cells = md.cell_count();
    for (std::int64_t e = 0; e < cells; ++e) {
      if (md.ghosts.is_ghost(e)) continue;
      ++f.real_cells;
      if (f.domain >= 0) continue;
      std::int64_t idx[8];
      Vec3 v[8];
      const int k = element_index_fault(a, e, md.coords.count, idx, v);
      if (k < 0) continue;
      f.domain = static_cast<std::int64_t>(i);
      f.cell = e;
      f.corner = k;
      f.index = idx[k];
      if (idx[k] >= 0 && idx[k] < md.coords.count) f.vertex = v[k];
    }
  }
  return f;
}

MeshValueStats mesh_value_stats_host(const Mesh& mesh) {
  MeshValueStats s;
  for (const MeshDomain& md : mesh.domains) {
    const DomainAccess a = DomainAccess::of(md);
    const bool cells = md.field.association == Association::Cell;
    for (std::int64_t e = 0; e < md.field.count; ++e) {
      const double v = a.value(e);
      s.nan += v != v ? 1 : 0;
      add_value(s.all, v);
      if (!(cells && md.ghosts.is_ghost(e)) && value_flag(v) == 0) add_value(s.real, v);
    }
    s.values += static_cast<std::uint64_t>(md.field.count);
  }
  return s;
}

FieldSummary::Parts mesh_summary_cells_host(const Mesh& mesh, const MacroGrid& g) {
  FieldSummary::Parts parts = empty_cells(g);
  std::vector<DomainAccess> access;
  for (const MeshDomain& md : mesh.domains) access.push_back(DomainAccess::of(md));
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const MeshDomain& md = mesh.domains[i];
    const std::int64_t cells = md.cell_count();
    for (std::int64_t e = 0; e < cells; ++e) {
      if (md.ghosts.is_ghost(e)) continue;
      double box[6];
      element_box(access[i], e, box);
      fold_into_cells(parts, g, box, element_range(access.data(), MeshElementRef{e, static_cast<std::int32_t>(i)}));
    }
  }
  return parts;
}

GeometrySums mesh_geometry_sums_host(const Mesh& mesh) { return geometry_sums(mesh); }

}  // namespace tessera::cuda

namespace tessera {

namespace {

MeshValueTotals totals_of(const cuda::MeshValueStats& s) {
  MeshValueTotals t;
  t.values = s.values;
  t.nan = s.nan;
  t.lo = s.all.lo;
  t.hi = s.all.hi;
  t.real_lo = s.real.lo;
  t.real_hi = s.real.hi;
  return t;
}

/// The summary over `v`, the mesh's value totals (what MeshTables counts: mesh_summary.cpp),
/// for edge >= 1.
std::shared_ptr<const FieldSummary> summary_with(const Mesh& mesh, const VolumeGeometry& grid,
                                                 const std::int64_t dims[3], int edge, const MeshValueTotals& v,
                                                 void* stream) {
  FieldSummary::Parts parts = cuda::mesh_summary_cells(mesh, macro_grid(grid, dims, edge), stream);
  parts.nan = v.nan;
  parts.elements = std::max<std::uint64_t>(1, v.values);
  parts.vmin = v.lo;
  parts.vmax = v.hi;
  FieldLayout layout;
  layout.dtype = DType::Float64;
  for (int a = 0; a < 3; ++a) layout.dims[a] = dims[a];
  return FieldSummary::from_parts(std::move(parts), layout, edge);
}

}  // namespace

MeshChecked cuda_check_mesh_indices(const Mesh& mesh, void* stream) {
  check_mesh_descriptors(mesh);
  const cuda::MeshIndexFault f = cuda::mesh_index_fault(mesh, stream);
  if (f.domain >= 0)
    throw_index_fault(static_cast<std::size_t>(f.domain), f.cell, f.corner, f.index,
                      mesh.domains[static_cast<std::size_t>(f.domain)].coords.count, f.vertex);
  if (f.real_cells == 0) throw std::invalid_argument("mesh: no real (non-ghost) cell in any domain");
  MeshChecked c = MeshCheckedIssuer::issue(mesh, false);
  MeshCheckedIssuer::record(c, totals_of(cuda::mesh_value_stats(mesh, stream)));
  return c;
}

std::shared_ptr<const FieldSummary> cuda_mesh_summary(const Mesh& mesh, const VolumeGeometry& grid,
                                                      const std::int64_t dims[3], int edge, void* stream,
                                                      const MeshChecked* checked) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  if (checked && checked->values() && checked->covers(mesh, false))
    return summary_with(mesh, grid, dims, edge, *checked->values(), stream);
  return summary_with(mesh, grid, dims, edge, totals_of(cuda::mesh_value_stats(mesh, stream)), stream);
}

MeshGeometryHash cuda_mesh_geometry_hash(const Mesh& mesh, void* stream) {
  check_mesh_descriptors(mesh);
  return finish_geometry_hash(mesh, cuda::mesh_geometry_sums(mesh, stream));
}

MeshGeometryHash cuda_mesh_ghost_sums(const Mesh& mesh, void* stream) {
  check_mesh_descriptors(mesh);
  if (!has_ghost_masks(mesh)) return {};
  const GeometrySums s = cuda::mesh_geometry_sums(ghost_masks_only(mesh), stream);
  return {s.a, s.b};
}

std::pair<double, double> cuda_mesh_value_range(const Mesh& mesh, void* stream) {
  const cuda::MeshValueStats s = cuda::mesh_value_stats(mesh, stream);
  return {s.real.lo, s.real.hi};
}

}  // namespace tessera
