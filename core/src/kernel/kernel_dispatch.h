#pragma once
/// with_kernel: the one place where a frame's run-time modes become template parameters.
/// Reads the KernelScene's field dtype (or PagedValue for a paged field), shading mode, emission flag, free-path strategy and
/// shadow estimator once and calls fn(KernelTraits<...>{}) with the concrete combination, so
/// kernels instantiated on K hold no branch on any of them per sample or per step.
#include <tessera/field_view.h>
#include <tessera/integrator.h>

#include "kernel/grid_medium.h"
#include "kernel/kernel_scene.h"

#include <type_traits>

namespace tessera {

/// The compile-time variant of one frame's kernel.
template <class T, Shading S, bool E, FreePath F, ShadowMode Sh>
struct KernelTraits {
  using Value = T;                         ///< field element type
  static constexpr Shading kShading = S;
  static constexpr bool kEmission = E;     ///< an emission TF exists
  static constexpr FreePath kFreePath = F;
  static constexpr ShadowMode kShadow = Sh;
};

namespace detail {

template <class T, Shading S, bool E, FreePath F, class Fn>
decltype(auto) with_shadow(const KernelScene& ks, Fn& fn) {
  if (ks.shadow == ShadowMode::Delta) return fn(KernelTraits<T, S, E, F, ShadowMode::Delta>{});
  return fn(KernelTraits<T, S, E, F, ShadowMode::Ratio>{});
}

template <class T, Shading S, bool E, class Fn>
decltype(auto) with_free_path(const KernelScene& ks, Fn& fn) {
  if (ks.free_path == FreePath::Raymarch) return with_shadow<T, S, E, FreePath::Raymarch>(ks, fn);
  return with_shadow<T, S, E, FreePath::Delta>(ks, fn);
}

template <class T, Shading S, class Fn>
decltype(auto) with_emission(const KernelScene& ks, Fn& fn) {
  if (ks.has_emission) return with_free_path<T, S, true>(ks, fn);
  return with_free_path<T, S, false>(ks, fn);
}

template <class T, class Fn>
decltype(auto) with_shading(const KernelScene& ks, Fn& fn) {
  switch (ks.shading) {
    case Shading::Phase: return with_emission<T, Shading::Phase>(ks, fn);
    case Shading::Brdf: return with_emission<T, Shading::Brdf>(ks, fn);
    case Shading::Hybrid: default: return with_emission<T, Shading::Hybrid>(ks, fn);
  }
}

}  // namespace detail

/// A type as a value, for with_value.
template <class T>
struct TypeTag {
  using type = T;
};

/// Calls fn(TypeTag<V>{}) with V the kernels' Value for the scene: PagedValue when the field
/// is paged (ks.paged.cache set), else the C++ type of the field's dtype.
template <class Fn>
decltype(auto) with_value(const KernelScene& ks, Fn&& fn) {
  if (ks.paged.cache != nullptr) return fn(TypeTag<PagedValue>{});
  return dispatch_dtype(ks.field, [&](auto view) -> decltype(auto) {
    return fn(TypeTag<typename decltype(view)::value_type>{});
  });
}

/// Calls fn(KernelTraits<V, ...>{}) for the scene's modes, with the Value V given.
template <class V, class Fn>
decltype(auto) with_modes(const KernelScene& ks, Fn&& fn) {
  return detail::with_shading<V>(ks, fn);
}

/// Calls fn(KernelTraits<...>{}) for the scene's variant and returns its result (every
/// instantiation of fn must return the same type).
template <class Fn>
decltype(auto) with_kernel(const KernelScene& ks, Fn&& fn) {
  return with_value(ks, [&](auto tag) -> decltype(auto) {
    return detail::with_shading<typename decltype(tag)::type>(ks, fn);
  });
}

/// The kernels' medium over the scene's field (trivially copyable; points into ks).
template <class T>
GridMedium<T> make_medium(const KernelScene& ks) {
  GridMedium<T> m;
  if constexpr (std::is_same_v<T, PagedValue>) m.field = ks.paged;
  else m.field = typed<T>(ks.field);
  for (int a = 0; a < 3; ++a) {
    m.n[a] = ks.field.dims[a];
    m.hi_index[a] = static_cast<double>(ks.field.dims[a] - 1);
    m.nc[a] = ks.cells[a];
  }
  m.tf = ks.tf;
  m.sigma_max = ks.sigma_max;
  m.majorant = ks.majorant;
  m.cell_edge = ks.cell_edge;
  return m;
}

}  // namespace tessera
