#pragma once
/// MeshLayout: what MeshTables (mesh_tables.h) builds from a mesh's geometry alone (its
/// coordinates, connectivity, dims, shapes and ghost masks; never its values), so that
/// prepares of the same mesh with other values can share it: the real elements in canonical
/// order with their boxes, the grid laid over the mesh's box and the location cells' lists.
/// Immutable once built; shared as std::shared_ptr<const MeshLayout> (render.h).
///
/// The canonical order is a function of each element's own vertex coordinates: its centroid
/// (x, then y, then z), then its box, then its vertices' coordinates in its own vertex order,
/// so that it does not depend on how the cells are cut into domains or ordered, nor on the
/// values.
#include <tessera/mesh.h>
#include <tessera/scene.h>

#include "mesh/domain_access.h"
#include "mesh/geometry_hash.h"
#include "mesh/macro_spans.h"
#include "mesh/mesh_field_view.h"

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace tessera {

class MeshLayout {
 public:
  /// Builds the layout of `mesh` (which check_mesh has accepted); `domains`: its domains'
  /// DomainAccess, in order.
  MeshLayout(const Mesh& mesh, const std::vector<DomainAccess>& domains);

  /// True iff `mesh` has this layout's domains with the same shapes and counts (domain count,
  /// dims, shape, index type, cells, vertices, coordinate dtype, ghost mask or none): the
  /// cheap part of "the same mesh". Whether the coordinates, indices and ghost flags are the
  /// same is the caller's promise (it is not checked: that would take the build's pass).
  bool fits(const Mesh& mesh) const;

  std::size_t element_count() const { return m_element.size(); }
  const MeshElementRef& element(std::size_t e) const { return m_element[e]; }
  const double* box(std::size_t e) const { return &m_box[6 * e]; }
  const std::int64_t* dims() const { return m_dims; }
  /// The input's domains and each one's cells (ghosts included), as the layout was built over.
  std::size_t domain_count() const;
  std::int64_t domain_cells(std::size_t d) const;
  /// The grid over the mesh's box: vertex-centred, uniform, dims() vertices per axis.
  VolumeGeometry geometry() const;
  /// The kernels' view with `domains` (the current arrays); element null when empty.
  MeshFieldView view(const DomainAccess* domains) const;
  std::uint64_t bytes() const;
  /// The item sums of the ghost masks the layout was built over (geometry_hash.h,
  /// ghost_masks_only; zero without masks): what a later mesh's masks must sum to for the
  /// layout's elements to be its real cells.
  const GeometrySums& ghost_sums() const { return m_ghost_sums; }

  /// Where a copy of these tables in a GPU's memory is kept between calls (made by the first
  /// GPU render over this layout, cuda/device_mesh_tables.h; released with the layout), so that
  /// later renders over the same layout (a mesh reused across calls) read it instead of copying
  /// the tables again. The one mutable part of a layout: guarded by its mutex.
  struct DeviceCopySlot {
    std::mutex mutex;
    std::shared_ptr<const void> copy;
  };
  DeviceCopySlot& device_copy_slot() const { return m_device_copy; }

  /// The elements' macrocell spans over `grid` (macro_spans.h), made by the first call for that
  /// grid and kept (one grid at a time: another grid replaces them) for the summaries of later
  /// prepares that reuse this layout. Counted in bytes() once made. Thread-safe.
  std::shared_ptr<const MacroSpans> macro_spans(const MacroGrid& grid) const;

 private:
  /// Returns each element's centroid x (canonical order), for slab_runs.
  std::vector<double> gather(const std::vector<DomainAccess>& domains, const Mesh& mesh);
  void place_grid();
  void build_location(const std::vector<double>& centroid_x);

  std::vector<std::int64_t> m_signature;  ///< per domain, what fits() compares
  std::vector<MeshElementRef> m_element;
  std::vector<double> m_box;
  std::vector<std::uint64_t> m_first;
  std::vector<std::uint32_t> m_list;
  Vec3 m_lo{0.0}, m_hi{0.0}, m_spacing{1.0};
  std::int64_t m_dims[3] = {2, 2, 2};
  Vec3 m_loc_lo{0.0}, m_loc_inv{1.0};
  std::int64_t m_loc_n[3] = {1, 1, 1};
  GeometrySums m_ghost_sums;
  mutable DeviceCopySlot m_device_copy;
  mutable std::mutex m_spans_mutex;
  mutable std::shared_ptr<const MacroSpans> m_spans;
};

}  // namespace tessera
