#pragma once
/// MeshFieldView: how the kernels read a curvilinear or unstructured mesh (mesh.h) in the
/// medium's p space (grid_medium.h: world x = origin + p * spacing of the uniform grid that
/// prepare() lays over the mesh's box). Trivially copyable; points into the tables that
/// prepare() built (mesh_tables.h) and into the caller's arrays.
///
/// Point location: a uniform grid of location cells over the box (its walls half a cell off
/// the medium's voxel walls), each listing the elements whose bounding box meets it, in the
/// elements' canonical order (mesh_tables.h). A lookup finds its location cell in O(1) (no
/// search from a root) and takes the first listed element that holds the point within
/// kInsideSlack: since the order is a function of each element's own vertex coordinates
/// (mesh_layout.h), a point on a shared face takes the same element however the mesh is cut into
/// domains or ordered. A point in no element is outside the mesh: empty space (the medium's
/// extinction there is 0; value() returns false).
///
/// Reconstruction (physics.md section 10): vertex data is barycentric on a tet and trilinear
/// in the hex's parametric coordinates (Newton's inverse), each clamped to the element so that
/// the value is a convex combination of its vertex values (the majorants bound it); cell data
/// is the cell's value. NaN and -Inf values read as nf_lo, +Inf as nf_hi (as on grids).
/// Host and device code (host_device.h): the CUDA backend reads a mesh through the same view
/// over its device copies of the tables and arrays (cuda/device_scene.h).
#include <tessera/host_device.h>
#include <tessera/math.h>

#include "mesh/domain_access.h"
#include "mesh/element_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace tessera {

/// The kernels' Value for a curvilinear or unstructured mesh (kernel/mesh_medium.h).
struct MeshValue {};

/// Where one element's data is: its domain and its cell there.
struct MeshElementRef {
  std::int64_t cell = 0;
  std::int32_t domain = 0;
};

struct MeshFieldView {
  const DomainAccess* domain = nullptr;
  const MeshElementRef* element = nullptr;  ///< null: not a mesh
  const double* box = nullptr;              ///< per element lo x, y, z, hi x, y, z (world)
  const std::uint64_t* first = nullptr;     ///< per location cell, x fastest, and one past: its list's start
  const std::uint32_t* list = nullptr;      ///< element indices, each cell's in canonical order
  Vec3 origin{0.0}, spacing{1.0};           ///< the medium's p space: x = origin + p * spacing
  Vec3 loc_lo{0.0}, loc_inv{1.0};           ///< location cell of x: floor((x - loc_lo) * loc_inv)
  std::int64_t loc_n[3] = {1, 1, 1};

  /// The field at p into *out; false when p lies in no element (outside the mesh). Out of
  /// line in device code (host_device.h), as element_value: the kernel's code halves.
  TESSERA_DEVICE_NOINLINE TESSERA_HOST_DEVICE bool value(const Vec3& p, double nf_lo, double nf_hi, double* out) const {
    const Vec3 x = origin + p * spacing;
    std::int64_t c[3];
    for (int a = 0; a < 3; ++a) {
      const double q = std::floor((x[a] - loc_lo[a]) * loc_inv[a]);
      if (!(q >= 0.0 && q < static_cast<double>(loc_n[a]))) return false;
      c[a] = static_cast<std::int64_t>(q);
    }
    const std::int64_t cell = (c[2] * loc_n[1] + c[1]) * loc_n[0] + c[0];
    for (std::uint64_t i = first[cell], end = first[cell + 1]; i < end; ++i) {
      const std::uint32_t e = list[i];
      const double* b = box + 6 * static_cast<std::size_t>(e);
      if (x.x < b[0] || x.y < b[1] || x.z < b[2] || x.x > b[3] || x.y > b[4] || x.z > b[5]) continue;
      if (element_value(element[e], x, nf_lo, nf_hi, out)) return true;
    }
    return false;
  }

  /// The value of element r at x into *out if x lies in it.
  TESSERA_DEVICE_NOINLINE TESSERA_HOST_DEVICE bool element_value(const MeshElementRef& r, const Vec3& x, double nf_lo,
                                                                 double nf_hi, double* out) const {
    const DomainAccess& d = domain[r.domain];
    std::int64_t idx[8];
    Vec3 v[8];
    d.cell_vertices(r.cell, idx);
    for (int k = 0; k < d.nv; ++k) v[k] = d.vertex(idx[k]);
    double w[8];
    if (d.shape == Shape::Tet) {
      if (!tet_weights(v, x, w)) return false;
    } else if (!hex_weights_at(v, x, w)) {
      return false;
    }
    const auto finite = [&](double s) { return std::isfinite(s) ? s : (s > 0.0 ? nf_hi : nf_lo); };
    if (d.cell_data) {
      *out = finite(d.value(r.cell));
      return true;
    }
    double s = 0.0;
    for (int k = 0; k < d.nv; ++k) s += w[k] * finite(d.value(idx[k]));
    *out = s;
    return true;
  }

  /// Barycentric weights of x in tet v, clamped to the tet; false outside it.
  TESSERA_HOST_DEVICE static bool tet_weights(const Vec3* v, const Vec3& x, double w[4]) {
    if (!tet_barycentric(v, x, w)) return false;
    double sum = 0.0;
    for (int k = 0; k < 4; ++k) {
      if (!(w[k] >= -kInsideSlack)) return false;
      w[k] = std::max(w[k], 0.0);
      sum += w[k];
    }
    for (int k = 0; k < 4; ++k) w[k] /= sum;
    return true;
  }

  /// Trilinear weights of x in hex v (Newton's inverse, clamped to the unit cube); false
  /// outside it or where Newton's method does not converge.
  TESSERA_HOST_DEVICE static bool hex_weights_at(const Vec3* v, const Vec3& x, double w[8]) {
    double r[3];
    if (!hex_inverse(v, x, r) || !inside_unit(r)) return false;
    for (double& a : r) a = std::clamp(a, 0.0, 1.0);
    hex_weights(r, w);
    return true;
  }
};
static_assert(std::is_trivially_copyable_v<MeshFieldView>);

}  // namespace tessera
