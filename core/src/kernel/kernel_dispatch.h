#pragma once
/// with_value: the one place where a frame's run-time variant becomes a template parameter.
/// Reads the KernelScene's field dtype (or PagedValue for a paged field) once and calls the
/// kernels instantiated on that Value, so the field lookups of the tracking loops hold no
/// branch on the dtype. The other modes are read from the KernelScene where they act, each
/// once per ray or collision, never per step: the free-path strategy and the shadow estimator
/// pick one of two tracking loops (each a template, path_tracer.h), the shading mode and the
/// emission TF what a real collision evaluates. As template parameters of the whole kernel
/// they made 24 times the variants to compile and measured no faster (docs/BENCHMARKS.md,
/// "Kernel build cost").
#include <tessera/field_view.h>

#include "kernel/axis_map.h"
#include "kernel/grid_medium.h"
#include "kernel/kernel_scene.h"
#include "kernel/mesh_medium.h"

#include <type_traits>

namespace tessera {

/// A type as a value, for with_value.
template <class T>
struct TypeTag {
  using type = T;
};

/// Calls fn(TypeTag<V>{}) with V the kernels' Value for the scene: AmrValue for a hierarchy of
/// refinement levels (ks.amr.nlevels > 0), MagnitudeValue for a vector's magnitude
/// (ks.magnitude active), PagedValue when the field
/// is paged (ks.paged.cache set), else the C++ type of the field's dtype; wrapped in
/// Rectilinear<> when some axis is rectilinear.
template <class Fn>
decltype(auto) with_value(const KernelScene& ks, Fn&& fn) {
  if (ks.amr.nlevels > 0) return fn(TypeTag<AmrValue>{});
  if (ks.mesh.element != nullptr) return fn(TypeTag<MeshValue>{});  // a mesh (kernel/mesh_medium.h)
  const bool rect = ks.axis[0].coords || ks.axis[1].coords || ks.axis[2].coords;
  if (ks.magnitude.active()) return rect ? fn(TypeTag<Rectilinear<MagnitudeValue>>{}) : fn(TypeTag<MagnitudeValue>{});
  if (ks.paged.cache != nullptr) return rect ? fn(TypeTag<Rectilinear<PagedValue>>{}) : fn(TypeTag<PagedValue>{});
  return dispatch_dtype(ks.field, [&](auto view) -> decltype(auto) {
    using T = typename decltype(view)::value_type;
    return rect ? fn(TypeTag<Rectilinear<T>>{}) : fn(TypeTag<T>{});
  });
}

/// The kernels' medium over the scene's field (trivially copyable; points into ks).
template <class T>
GridMedium<T> make_medium(const KernelScene& ks) {
  GridMedium<T> m;
  using Base = typename ValueTraits<T>::base;
  if constexpr (std::is_same_v<Base, AmrValue>) m.field = ks.amr;
  else if constexpr (std::is_same_v<Base, PagedValue>) m.field = ks.paged;
  else if constexpr (std::is_same_v<Base, MeshValue>) m.field = ks.mesh;
  else if constexpr (std::is_same_v<Base, MagnitudeValue>) m.field = ks.magnitude;
  else m.field = typed<Base>(ks.field);
  for (int a = 0; a < 3; ++a) {
    m.n[a] = ks.field.dims[a];
    m.hi_index[a] = static_cast<double>(ks.field.dims[a] - 1);
    m.nc[a] = ks.cells[a];
    m.box_lo[a] = ks.box_lo[a];
    m.box_hi[a] = ks.box_hi[a];
    m.axis[a] = ks.axis[a];
  }
  m.outer_half = ks.outer_half;
  m.tf = ks.tf;
  m.sigma_max = ks.sigma_max;
  m.majorant = ks.majorant;
  m.empty_reach = ks.empty_reach;
  m.cell_edge = ks.cell_edge;
  return m;
}

}  // namespace tessera
