/// Which Values the device kernels hold, and the run-time variant of the frame turned into the
/// launch of the kernel instantiated on it (pixel_kernel.h): the same choice as with_value
/// (kernel/kernel_dispatch.h) makes for the CPU's kernels, restricted to what the device covers.
#include "cuda/cuda_check.h"
#include "cuda/pixel_kernel.h"
#include "kernel/kernel_dispatch.h"

#include <cuda_runtime_api.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <type_traits>

namespace tessera::cuda {

namespace {

/// fn(TypeTag<V>{}) for the Value with_value picks, when the device kernels hold it; false
/// when they do not.
template <class Fn>
bool with_device_value(const KernelScene& ks, Fn&& fn) {
  if (ks.mesh.element != nullptr || ks.paged.cache != nullptr) return false;
  // Refinement levels: not on the device yet (its first GPU run drew more samples than the
  // image has and differed from run to run; refused until that is understood)
  if (ks.amr.nlevels > 0) return false;
  const bool rect = ks.axis[0].coords || ks.axis[1].coords || ks.axis[2].coords;
  if (ks.magnitude.active()) {
    rect ? fn(TypeTag<Rectilinear<MagnitudeValue>>{}) : fn(TypeTag<MagnitudeValue>{});
    return true;
  }
  dispatch_dtype(ks.field, [&](auto view) {
    using T = typename decltype(view)::value_type;
    rect ? fn(TypeTag<Rectilinear<T>>{}) : fn(TypeTag<T>{});
  });
  return true;
}

}  // namespace

bool device_value_supported(const KernelScene& ks, std::string* why) {
  if (with_device_value(ks, [](auto) {})) return true;
  if (why) {
    if (ks.mesh.element != nullptr) *why = "a curvilinear or unstructured mesh";
    else if (ks.paged.cache != nullptr) *why = "a distributed (paged) field";
    else *why = "refinement levels";
  }
  return false;
}

std::string pixel_kernel_name(const KernelScene& ks) {
  std::string v;
  if (ks.amr.nlevels > 0) v = std::string("refinement levels, ") + dtype_name(ks.amr.dtype);
  else if (ks.magnitude.active()) v = "magnitude";
  else v = dtype_name(ks.field.dtype);
  if (ks.amr.nlevels == 0 && (ks.axis[0].coords || ks.axis[1].coords || ks.axis[2].coords)) v = "rectilinear " + v;
  return "pixel_samples<" + v + ">";
}

std::size_t device_medium_bytes(const KernelScene& ks) {
  std::size_t bytes = 0;
  with_device_value(ks, [&](auto tag) { bytes = sizeof(GridMedium<typename decltype(tag)::type>); });
  return bytes;
}

void make_device_medium(const KernelScene& ks_dev, void* out) {
  with_device_value(ks_dev, [&](auto tag) {
    using V = typename decltype(tag)::type;
    static_assert(std::is_trivially_copyable_v<GridMedium<V>>);
    *static_cast<GridMedium<V>*>(out) = make_medium<V>(ks_dev);
  });
}

int sample_lanes(int width, int height, int spp) {
  const std::int64_t pixels = std::max<std::int64_t>(1, static_cast<std::int64_t>(width) * height);
  const std::int64_t by_memory = (std::int64_t{1} << 22) / pixels;
  return static_cast<int>(std::max<std::int64_t>(1, std::min<std::int64_t>({8, spp, by_memory})));
}

void launch_pixel_slice(const KernelScene& ks, const SliceArgs& a, int block_threads) {
  const std::int64_t n = (a.j1 - a.j0) * a.lanes;
  if (n <= 0 || a.k1 <= a.k0) return;
  if (block_threads < 32 || block_threads > kMaxBlockThreads) block_threads = 128;
  const auto blocks = static_cast<unsigned>((n + block_threads - 1) / block_threads);
  with_device_value(ks, [&](auto tag) {
    using V = typename decltype(tag)::type;
    launch_pixel_samples<V>(a, blocks, static_cast<unsigned>(block_threads));
  });
  cuda_check(cudaGetLastError(), "launch of " + pixel_kernel_name(ks) + " (" + std::to_string(blocks) + " blocks of " +
                                     std::to_string(block_threads) + " threads, samples " + std::to_string(a.k0) +
                                     " to " + std::to_string(a.k1 - 1) + " of each pixel in " +
                                     std::to_string(a.lanes) + " lanes)");
}

}  // namespace tessera::cuda
