#pragma once
/// The CUDA kernel of the backend: one thread per pixel draws a slice of the pixel's samples
/// with the CPU's TileSampler (kernels/tile_sampler.h), so the random streams, the camera ray,
/// the estimator and the order of the pixel's sums are the CPU's, from the same headers.
/// Included by the pixel_kernel_*.cu files only, each instantiating a few Values
/// (TESSERA_PIXEL_KERNEL(V)): one instantiation is a large kernel, so they are spread over
/// files that compile in parallel.
#include "cuda/cuda_check.h"
#include "cuda/pixel_kernel.h"
#include "kernel/kernel_dispatch.h"
#include "kernels/tile_sampler.h"

// The out-of-line host functions the kernel calls, compiled here for the device only (the
// host keeps camera.cpp's and environment.cpp's symbols): one definition for both. Each .cu
// file is its own device module (no relocatable device code), so each holds its own copy.
#if defined(__CUDA_ARCH__)
#include "kernel/camera_ray.h"
#include "lights/environment_eval.h"
#endif

#include <cuda_runtime.h>

namespace tessera::cuda {

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

template <class V>
void launch_pixel_samples(const SliceArgs& a, unsigned blocks, unsigned threads) {
  pixel_samples<V><<<blocks, threads>>>(a);
}

}  // namespace tessera::cuda

/// Instantiates the kernel and its launch for Value V (at namespace scope of a .cu file).
#define TESSERA_PIXEL_KERNEL(V) \
  template void tessera::cuda::launch_pixel_samples<V>(const tessera::cuda::SliceArgs&, unsigned, unsigned)
