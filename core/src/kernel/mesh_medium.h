#pragma once
/// GridMedium<MeshValue>: the medium over a curvilinear or unstructured mesh (mesh.h). The
/// tracking loops, the macrocell walk and the majorants are the grid's, unchanged, over the
/// uniform grid that prepare() lays over the mesh's box (mesh/mesh_tables.h); only the field
/// lookups differ, specialised here (kernel_dispatch.h includes this header, so that every
/// translation unit that may instantiate the kernels on MeshValue sees the specialisations):
/// - value(p): the mesh's value where p lies in an element (mesh/mesh_field_view.h), NaN
///   outside every element;
/// - sigma_t(p): 0 outside every element (outside the mesh is empty space);
/// - gradient_voxel(p): central differences one voxel apart as on grids, one-sided where one
///   neighbour lies outside the mesh (0 along an axis where both do).
#include "kernel/grid_medium.h"
#include "mesh/mesh_field_view.h"

#include <algorithm>
#include <cmath>

namespace tessera {

template <>
struct FieldAccessor<MeshValue> {
  using type = MeshFieldView;
};

template <>
[[gnu::always_inline]] TESSERA_HOST_DEVICE inline double GridMedium<MeshValue>::value(const Vec3& p) const {
  double v;
  return field.value(p, tf->lo, tf->hi, &v) ? v : NAN;
}

template <>
[[gnu::always_inline]] TESSERA_HOST_DEVICE inline double GridMedium<MeshValue>::sigma_t(const Vec3& p) const {
  double v;
  if (!field.value(p, tf->lo, tf->hi, &v)) return 0.0;
  return sigma_t_of_u(tf->normalise(v));
}

template <>
TESSERA_HOST_DEVICE inline Vec3 GridMedium<MeshValue>::gradient_voxel(const Vec3& p) const {
  Vec3 g(0.0);
  const double u0 = u(p);
  for (int a = 0; a < 3; ++a) {
    Vec3 pm = p, pp = p;
    pm[a] = std::clamp(p[a] - 1.0, 0.0, hi_index[a]);
    pp[a] = std::clamp(p[a] + 1.0, 0.0, hi_index[a]);
    double um = u(pm), up = u(pp);
    if (std::isnan(um)) um = u0, pm[a] = p[a];
    if (std::isnan(up)) up = u0, pp[a] = p[a];
    const double h = pp[a] - pm[a];
    if (h > 0.0 && std::isfinite(um) && std::isfinite(up)) g[a] = (up - um) / h;
  }
  return g;
}

}  // namespace tessera
