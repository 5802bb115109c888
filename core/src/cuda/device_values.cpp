/// Which Values the device kernels hold (pixel_kernel.h), their names, the sample lanes and
/// the device medium of a frame's Value: host code of the device backend, in every build.
#include "cuda/device_value_dispatch.h"
#include "cuda/pixel_kernel.h"

#include <algorithm>
#include <cstdint>
#include <string>
#include <type_traits>

namespace tessera::cuda {

bool device_value_supported(const KernelScene& ks, std::string* why) {
  // Refinement levels: refused on a CUDA device by a build without their kernel
  // (-DTESSERA_CUDA_AMR=OFF; on by default). The host emulation runs them (emulated_device.h).
#if !defined(TESSERA_CUDA_AMR)
  if (ks.amr.nlevels > 0 && ks.amr.paged.cache == nullptr) {
    if (why) *why = "refinement levels";
    return false;
  }
#endif
  if (with_device_value(ks, [](auto) {})) return true;
  if (why) *why = "a distributed (paged) hierarchy of refinement levels";
  return false;
}

std::string pixel_kernel_name(const KernelScene& ks) {
  std::string v;
  if (ks.mesh.element != nullptr) return "pixel_samples<mesh>";
  if (ks.amr.nlevels > 0) v = std::string("refinement levels, ") + dtype_name(ks.amr.dtype);
  else if (ks.magnitude.active()) v = "magnitude";
  else if (ks.paged.cache != nullptr) v = std::string("distributed ") + dtype_name(ks.paged.dtype);
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
  // 32: one warp per pixel where the image is small enough (docs/gpu.md, "Sample lanes")
  constexpr std::int64_t kMaxLanes = 32;
  const std::int64_t pixels = std::max<std::int64_t>(1, static_cast<std::int64_t>(width) * height);
  const std::int64_t by_memory = (std::int64_t{1} << 22) / pixels;
  return static_cast<int>(std::max<std::int64_t>(1, std::min<std::int64_t>({kMaxLanes, spp, by_memory})));
}

}  // namespace tessera::cuda
