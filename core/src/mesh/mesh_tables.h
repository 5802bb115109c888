#pragma once
/// MeshTables: what prepare() builds over a checked mesh (check_mesh) for the kernels'
/// MeshFieldView, and the uniform grid laid over the mesh's box that the medium's p space,
/// the macrocell majorants and the rest of the renderer see (prepare(const Mesh&), render.h).
///
/// Build, O(n log n) in the real elements, single-threaded so that it is the same for any
/// thread count, and independent of how the cells are cut into domains or ordered:
/// - every real (non-ghost) element's bounding box, centroid and value range;
/// - the canonical order: elements sorted by centroid (x, then y, then z), then bounding box,
///   then value range, all computed from the element's own vertex coordinates and values;
/// - the grid: its box is the union of the elements' boxes; its voxel is the mean over the
///   elements of the cube root of their box's volume (a uniform grid's cells give back its
///   spacing), rounded to whole voxels per axis, at most 4 n + 64 voxels in all;
/// - location cells of one voxel, offset by half a voxel, each listing the elements whose box
///   (padded by 1e-7 of its size) meets it; where the lists would pass 64 entries per element
///   on average (long thin elements), the cells double in size until they do not.
#include <tessera/mesh.h>
#include <tessera/scene.h>

#include "mesh/domain_access.h"
#include "mesh/mesh_field_view.h"

#include <cstdint>
#include <vector>

namespace tessera {

/// Value range of one element (or of the elements meeting one macrocell): finite min / max
/// and bit 0 NaN, bit 1 +Inf, bit 2 -Inf among the values (FieldSummary::Parts' flags).
struct ElementRange {
  double lo = INFINITY, hi = -INFINITY;
  std::uint8_t flags = 0;
};

class MeshTables {
 public:
  /// Builds the tables of `mesh`, which check_mesh has accepted.
  void build(const Mesh& mesh);

  bool empty() const { return m_element.empty(); }
  /// The kernels' view (element null when empty()).
  MeshFieldView view() const;
  /// The grid over the mesh's box: vertex-centred, uniform, `dims()` vertices per axis.
  VolumeGeometry geometry() const;
  const std::int64_t* dims() const { return m_dims; }
  std::size_t element_count() const { return m_element.size(); }
  /// Element e's world box (lo x, y, z, hi x, y, z) and value range, in
  /// canonical order.
  const double* box(std::size_t e) const { return &m_box[6 * e]; }
  const ElementRange& range(std::size_t e) const { return m_range[e]; }
  /// NaN values, finite min / max and the count of all values of the mesh (ghosts' too).
  std::uint64_t nan_values() const { return m_nan; }
  std::uint64_t value_count() const { return m_values; }
  double value_min() const { return m_vmin; }
  double value_max() const { return m_vmax; }
  /// Bytes these tables hold.
  std::uint64_t bytes() const;

 private:
  void gather(const Mesh& mesh);
  void place_grid();
  void build_location();
  void count_values(const Mesh& mesh);

  std::vector<DomainAccess> m_domain;
  std::vector<MeshElementRef> m_element;
  std::vector<double> m_box;
  std::vector<ElementRange> m_range;
  std::vector<std::uint64_t> m_first;
  std::vector<std::uint32_t> m_list;
  Vec3 m_lo{0.0}, m_hi{0.0}, m_spacing{1.0};
  std::int64_t m_dims[3] = {2, 2, 2};
  Vec3 m_loc_lo{0.0}, m_loc_inv{1.0};
  std::int64_t m_loc_n[3] = {1, 1, 1};
  std::uint64_t m_nan = 0, m_values = 0;
  double m_vmin = INFINITY, m_vmax = -INFINITY;
};

}  // namespace tessera
