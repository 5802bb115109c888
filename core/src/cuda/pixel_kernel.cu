/// The CUDA kernel of the backend: one thread per pixel draws a slice of the pixel's samples
/// with the CPU's TileSampler (kernels/tile_sampler.h), so the random streams, the camera ray,
/// the estimator and the order of the pixel's sums are the CPU's, from the same headers.
/// Instantiated for uniform float32 and float64 fields.
#include "cuda/pixel_kernel.h"

#include "cuda/cuda_check.h"
#include "kernel/kernel_dispatch.h"
#include "kernels/tile_sampler.h"

// The out-of-line host functions the kernel calls, compiled here for the device only (the
// host keeps camera.cpp's and environment.cpp's symbols): one definition for both.
#if defined(__CUDA_ARCH__)
#include "kernel/camera_ray.h"
#include "lights/environment_eval.h"
#endif

#include <cuda_runtime.h>

#include <string>

namespace tessera::cuda {

namespace {

constexpr int kMaxBlockThreads = 256;

template <class V>
__global__ void __launch_bounds__(kMaxBlockThreads) pixel_samples(SliceArgs a) {
  const std::int64_t j = a.j0 + static_cast<std::int64_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (j >= a.j1) return;
  const PixelJob job = a.jobs[j];
  TileSampler<V> ts(*a.ks, *static_cast<const GridMedium<V>*>(a.medium), job.culled != 0, nullptr);
  PixelSums px = a.px[j];
  AuxSums aux;
  if (a.aux) aux = a.aux[j];
  RenderStats st;
  // The CPU's loop (sample_uniform, tile_kernel_impl.h): each sample continues at px.drawn
  for (int s = 0; s < a.samples; ++s) ts.accumulate(job.x, job.y, px, a.aux ? &aux : nullptr, px.drawn, st);
  a.px[j] = px;
  if (a.aux) a.aux[j] = aux;
  // Integer sums: the same whatever order the threads add them in
  const RenderStats& k = ts.counters();
  unsigned long long* c = a.counters;
  atomicAdd(&c[kSamples], static_cast<unsigned long long>(st.samples));
  atomicAdd(&c[kDiscardedSamples], static_cast<unsigned long long>(st.discarded_samples));
  atomicAdd(&c[kFreeFlightLookups], static_cast<unsigned long long>(k.free_flight_lookups));
  atomicAdd(&c[kTransmittanceLookups], static_cast<unsigned long long>(k.transmittance_lookups));
  atomicAdd(&c[kGradientLookups], static_cast<unsigned long long>(k.gradient_lookups));
  atomicAdd(&c[kRealCollisions], static_cast<unsigned long long>(k.real_collisions));
  atomicAdd(&c[kNullCollisions], static_cast<unsigned long long>(k.null_collisions));
  atomicAdd(&c[kStalledPaths], static_cast<unsigned long long>(k.stalled_paths));
}

/// fn(TypeTag<V>{}) for the Values the device kernels hold; false when ks's is not one.
template <class Fn>
bool with_device_value(const KernelScene& ks, Fn&& fn) {
  const bool plain = ks.amr.nlevels == 0 && ks.mesh.element == nullptr && !ks.magnitude.active() &&
                     ks.paged.cache == nullptr && !ks.axis[0].coords && !ks.axis[1].coords && !ks.axis[2].coords;
  if (!plain) return false;
  if (ks.field.dtype == DType::Float32) fn(TypeTag<float>{});
  else if (ks.field.dtype == DType::Float64) fn(TypeTag<double>{});
  else return false;
  return true;
}

}  // namespace

bool device_value_supported(const KernelScene& ks, std::string* why) {
  if (with_device_value(ks, [](auto) {})) return true;
  if (why) {
    if (ks.amr.nlevels > 0) *why = "refinement levels";
    else if (ks.mesh.element != nullptr) *why = "a curvilinear or unstructured mesh";
    else if (ks.magnitude.active()) *why = "a vector's magnitude";
    else if (ks.paged.cache != nullptr) *why = "a distributed (paged) field";
    else if (ks.axis[0].coords || ks.axis[1].coords || ks.axis[2].coords) *why = "rectilinear axes";
    else *why = std::string("a ") + dtype_name(ks.field.dtype) + " field (float32 and float64 only)";
  }
  return false;
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

void launch_pixel_slice(const KernelScene& ks, const SliceArgs& a, int block_threads) {
  const std::int64_t n = a.j1 - a.j0;
  if (n <= 0 || a.samples <= 0) return;
  if (block_threads < 32 || block_threads > kMaxBlockThreads) block_threads = 128;
  const auto blocks = static_cast<unsigned>((n + block_threads - 1) / block_threads);
  with_device_value(ks, [&](auto tag) {
    using V = typename decltype(tag)::type;
    pixel_samples<V><<<blocks, static_cast<unsigned>(block_threads)>>>(a);
    cuda_check(cudaGetLastError(), std::string("launch of pixel_samples<") + dtype_name(ks.field.dtype) + "> (" +
                                       std::to_string(blocks) + " blocks of " + std::to_string(block_threads) +
                                       " threads, " + std::to_string(a.samples) + " samples per pixel)");
  });
}

}  // namespace tessera::cuda
