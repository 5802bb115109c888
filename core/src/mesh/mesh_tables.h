#pragma once
/// MeshTables: what prepare() builds over a checked mesh (check_mesh) for the kernels'
/// MeshFieldView, and the uniform grid laid over the mesh's box that the medium's p space,
/// the macrocell majorants and the rest of the renderer see (prepare(const Mesh&), render.h).
///
/// Build: the layout (mesh_layout.h: the real elements in canonical order, their boxes, the
/// grid over the mesh's box and the location cells; O(n log n), single-threaded so that it is
/// the same for any thread count, independent of how the cells are cut into domains or
/// ordered, and of the values), built or shared with an earlier build of the same mesh; then
/// the readers of the current arrays. The values' totals (value_totals) and the elements'
/// value ranges (min / max of the vertex values, or the cell value, folded straight into the
/// macrocells in the input's order) are mesh_summary's, over all of them or one share.
/// - The grid: its box is the union of the elements' boxes; its voxel is the mean over the
///   elements of the cube root of their box's volume (a uniform grid's cells give back its
///   spacing), rounded to whole voxels per axis, at most 4 n + 64 voxels in all.
/// - Location cells of one voxel, offset by half a voxel, each listing the elements whose box
///   (padded by 1e-7 of its size) meets it; where the lists would pass 64 entries per element
///   on average (long thin elements), the cells double in size until they do not.
#include <tessera/mesh.h>
#include <tessera/scene.h>

#include "mesh/domain_access.h"
#include "mesh/element_range.h"
#include "mesh/mesh_field_view.h"
#include "mesh/mesh_layout.h"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace tessera {

class MeshTables {
 public:
  /// Builds the tables of `mesh`, which check_mesh has accepted: its layout (`reuse` when it
  /// fits the mesh: the caller's promise that the geometry is that layout's; else built), then
  /// binds the mesh's current arrays. A reused layout with an element that is a ghost now is
  /// refused by name (std::invalid_argument).
  void build(const Mesh& mesh, std::shared_ptr<const MeshLayout> reuse = nullptr);
  /// The tables of a mesh in device memory (Mesh::device), whose values a device summarises
  /// (cuda_mesh_summary, cuda_render.h): `layout` (which fits it) and the readers of its
  /// arrays (value_totals must not be used: the device folds the totals into the summary).
  void build_on_device(const Mesh& mesh, std::shared_ptr<const MeshLayout> layout);
  /// Built by build_on_device: the arrays are device memory, read on the device only.
  bool on_device() const { return m_on_device; }

  bool empty() const { return !m_layout || m_layout->element_count() == 0; }
  /// The kernels' view (element null when empty()).
  MeshFieldView view() const;
  /// The grid over the mesh's box: vertex-centred, uniform, `dims()` vertices per axis.
  VolumeGeometry geometry() const { return m_layout->geometry(); }
  const std::int64_t* dims() const { return m_layout->dims(); }
  std::size_t element_count() const { return m_layout ? m_layout->element_count() : 0; }
  /// The domains' readers the view points to (one per domain, in order).
  std::span<const DomainAccess> domains() const { return m_domain; }
  /// Per domain, where each array the readers point into lies (MeshArraySlot order): its
  /// span (mesh_array) and the GPU copy of it the caller named (MeshDomain::device_copy), for
  /// a device render's copies (cuda/device_scene.h).
  struct DomainArrays {
    std::array<MeshArraySpan, kMeshArraySlots> span;
    std::array<const void*, kMeshArraySlots> device_copy;
  };
  std::span<const DomainArrays> arrays() const { return m_arrays; }
  /// Element e's world box (lo x, y, z, hi x, y, z), in canonical order.
  const double* box(std::size_t e) const { return m_layout->box(e); }
  /// The NaN values, finite min / max (zeros as +0.0: the same bits in any split) and count of
  /// the values [v0, v1) of every domain's field in order (ghosts' too), over threads.
  struct ValueTotals {
    std::uint64_t nan = 0, count = 0;
    double lo = INFINITY, hi = -INFINITY;
  };
  ValueTotals value_totals(std::uint64_t v0, std::uint64_t v1) const;
  /// Every domain's field count, summed.
  std::uint64_t value_count() const { return static_cast<std::uint64_t>(m_value_offset.back()); }
  /// The layout, to share with the next build of the same mesh; whether this one was reused.
  const std::shared_ptr<const MeshLayout>& layout() const { return m_layout; }
  bool layout_reused() const { return m_reused; }
  /// Bytes these tables hold (the layout included).
  std::uint64_t bytes() const;

 private:
  void refuse_new_ghosts(const Mesh& mesh) const;
  void bind(const Mesh& mesh);

  std::shared_ptr<const MeshLayout> m_layout;
  bool m_reused = false;
  bool m_on_device = false;
  std::vector<DomainAccess> m_domain;  ///< the current arrays
  std::vector<DomainArrays> m_arrays;
  std::vector<std::int64_t> m_value_offset{0};  ///< per domain its first value, then the total
};

}  // namespace tessera
