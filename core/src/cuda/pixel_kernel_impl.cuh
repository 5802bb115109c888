#pragma once
/// The CUDA kernel of the backend: one thread per sample lane runs draw_lane (lane_kernel.h,
/// the CPU's TileSampler, kernels/tile_sampler.h), so the random streams, the camera ray, the
/// estimator and the order of the pixel's sums are the CPU's, from the same headers.
/// Included by the pixel_kernel_*.cu files only, each instantiating a few Values
/// (TESSERA_PIXEL_KERNEL(V)): one instantiation is a large kernel, so they are spread over
/// files that compile in parallel.
#include "cuda/cuda_check.h"
#include "kernels/lane_kernel.h"
#include "cuda/pixel_kernel.h"
#include "kernel/kernel_dispatch.h"

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
  unsigned long long c[kCounterCount];
  if (!draw_lane<V>(a, static_cast<std::int64_t>(blockIdx.x) * blockDim.x + threadIdx.x, c)) return;
#pragma unroll
  for (int i = 0; i < kCounterCount; ++i) atomicAdd(&a.counters[i], c[i]);
}

template <class V>
void launch_pixel_samples(const SliceArgs& a, unsigned blocks, unsigned threads) {
  pixel_samples<V><<<blocks, threads>>>(a);
}

}  // namespace tessera::cuda

/// Instantiates the kernel and its launch for Value V (at namespace scope of a .cu file).
#define TESSERA_PIXEL_KERNEL(V) \
  template void tessera::cuda::launch_pixel_samples<V>(const tessera::cuda::SliceArgs&, unsigned, unsigned)
