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
  // Thread t: lane t % lanes of job j0 + t / lanes (a pixel's lanes side by side: their rays
  // run together)
  const std::int64_t t = static_cast<std::int64_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  const std::int64_t j = a.j0 + t / a.lanes;
  if (j >= a.j1) return;
  const int lane = static_cast<int>(t % a.lanes);
  const PixelJob job = a.jobs[j];
  TileSampler<V> ts(*a.ks, *static_cast<const GridMedium<V>*>(a.medium), job.culled != 0, nullptr);
  const std::uint64_t drawn0 = a.px[j].drawn;
  const std::int64_t q = j * a.lanes + lane;
  PixelSums px = a.lane_px[q];
  AuxSums aux;
  if (a.lane_aux) aux = a.lane_aux[q];
  RenderStats st;
  // The CPU's estimator (sample_uniform, tile_kernel_impl.h) for this lane's samples, in index
  // order: k = lane (mod lanes) within [k0, k1)
  const int first = a.k0 + ((lane - a.k0 % a.lanes) % a.lanes + a.lanes) % a.lanes;
  for (int k = first; k < a.k1; k += a.lanes)
    ts.accumulate(job.x, job.y, px, a.lane_aux ? &aux : nullptr, drawn0 + static_cast<std::uint64_t>(k), st);
  a.lane_px[q] = px;
  if (a.lane_aux) a.lane_aux[q] = aux;
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
