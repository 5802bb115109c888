#pragma once
/// with_device_value: the run-time variant of the frame turned into the device kernels' Value,
/// the same choice as with_value (kernel/kernel_dispatch.h) makes for the CPU's kernels,
/// restricted to what the kernel source can run on a device. Host code of the device backend.
#include "kernel/kernel_dispatch.h"

#include <type_traits>

namespace tessera::cuda {

/// Whether float32 fields have their own device kernel (read as they are) or are widened.
#if defined(TESSERA_CUDA_FLOAT32)
inline constexpr bool kFloat32Kernel = true;
#else
inline constexpr bool kFloat32Kernel = false;
#endif

/// fn(TypeTag<V>{}) for the device kernels' Value of `ks`, and true; false (fn not called) for
/// what they cannot run: hierarchies of refinement levels with remote patches. A distributed
/// (paged) field's Value is PagedValue (its dtype read per load), every vertex but the own
/// block's read through the device's bricks (device_bricks.h). A float32 field's Value is
/// float, read in place (kFloat32Kernel, TESSERA_CUDA_FLOAT32, on by default); a build with
/// -DTESSERA_CUDA_FLOAT32=OFF renders the float64 copy it widens (widen_field.h). A mesh's
/// values are read per load in their dtype (mesh/domain_access.h): one MeshValue kernel for
/// every dtype.
template <class Fn>
bool with_device_value(const KernelScene& ks, Fn&& fn) {
  if (ks.amr.nlevels > 0) {
    if (ks.amr.paged.cache != nullptr) return false;
    fn(TypeTag<AmrValue>{});
    return true;
  }
  if (ks.mesh.element != nullptr) {
    fn(TypeTag<MeshValue>{});
    return true;
  }
  const bool rect = ks.axis[0].coords || ks.axis[1].coords || ks.axis[2].coords;
  if (ks.magnitude.active()) {
    rect ? fn(TypeTag<Rectilinear<MagnitudeValue>>{}) : fn(TypeTag<MagnitudeValue>{});
    return true;
  }
  if (ks.paged.cache != nullptr) {
    rect ? fn(TypeTag<Rectilinear<PagedValue>>{}) : fn(TypeTag<PagedValue>{});
    return true;
  }
  dispatch_dtype(ks.field, [&](auto view) {
    using T0 = typename decltype(view)::value_type;
    using T = std::conditional_t<std::is_same_v<T0, float> && !kFloat32Kernel, double, T0>;
    rect ? fn(TypeTag<Rectilinear<T>>{}) : fn(TypeTag<T>{});
  });
  return true;
}

}  // namespace tessera::cuda
