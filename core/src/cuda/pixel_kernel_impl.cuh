#pragma once
/// The CUDA kernel of the backend: one thread per sample lane runs draw_lane (lane_kernel.h,
/// the CPU's TileSampler, kernels/tile_sampler.h), so the random streams, the camera ray, the
/// estimator and the order of the pixel's sums are the CPU's, from the same headers.
/// Included by the pixel_kernel_*.cu files only, each instantiating a few Values
/// (TESSERA_PIXEL_KERNEL(V)): one instantiation is a large kernel, so they are spread over
/// files that compile in parallel.
#include "cuda/cuda_check.h"
#include "kernels/lane_kernel.h"
#include "kernels/wave_kernel.h"
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

#include <string>

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

#if defined(TESSERA_CUDA_WAVEFRONT)
// The wavefront loop's kernels (kernels/wave_kernel.h): one thread per slot or queue entry (a
// queue's kernel covers every slot; the entries past its count, read on the device, return)
template <class V>
__global__ void __launch_bounds__(kMaxBlockThreads) wave_begin_slots(WaveArgs w) {
  const std::int64_t i = static_cast<std::int64_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < w.nslots) wave_begin<V>(w, i);
}
template <class V>
__global__ void __launch_bounds__(kMaxBlockThreads) wave_between_slots(WaveArgs w, int p) {
  wave_between<V>(w, p, static_cast<std::int64_t>(blockIdx.x) * blockDim.x + threadIdx.x);
}
template <class V>
__global__ void __launch_bounds__(kMaxBlockThreads) wave_walks(WaveArgs w, int p) {
  wave_walk<V>(w, p, static_cast<std::int64_t>(blockIdx.x) * blockDim.x + threadIdx.x);
}

template <class V>
void launch_wave_slice(const SliceArgs& a, unsigned threads, const WaveTuning& tuning) {
  if constexpr (kWaveCapable<V>) {
    const WaveArgs w = wave_args(a, tuning);
    const auto blocks = static_cast<unsigned>((w.nslots + threads - 1) / threads);
    const auto checked = [&](const char* what) {
      cuda_check(cudaGetLastError(), std::string("launch of the wavefront's ") + what + " (" + std::to_string(blocks) +
                                         " blocks of " + std::to_string(threads) + " threads)");
    };
    struct Ops {
      const WaveArgs& w;
      decltype(checked)& check;
      unsigned blocks, threads;
      void begin(std::int64_t) {
        wave_begin_slots<V><<<blocks, threads>>>(w);
        check("path slots' start");
      }
      void round(int p) {
        cuda_check(cudaMemsetAsync(&w.header->q[1 - p], 0, sizeof(WaveCounts)),
                   "cudaMemsetAsync(the wavefront's queue counts)");
        wave_between_slots<V><<<blocks, threads>>>(w, p);
        check("code between walks");
        wave_walks<V><<<blocks, threads>>>(w, p);
        check("walks");
      }
      unsigned long long pending(int q) const {
        WaveCounts c{};
        cuda_check(cudaMemcpy(&c, &w.header->q[q], sizeof c, cudaMemcpyDeviceToHost),
                   "the wavefront's rounds (their queue counts to the host)");
        return c.walks + c.betweens;
      }
    };
    drive_wave(w, Ops{w, checked, blocks, threads});
  } else {
    (void)a;
    (void)threads;
    (void)tuning;
  }
}
#endif

}  // namespace tessera::cuda

#if defined(TESSERA_CUDA_WAVEFRONT)
#define TESSERA_WAVE_SLICE(V) \
  template void tessera::cuda::launch_wave_slice<V>(const tessera::cuda::SliceArgs&, unsigned, \
                                                    const tessera::cuda::WaveTuning&);
#else
#define TESSERA_WAVE_SLICE(V)
#endif

/// Instantiates the kernel and its launch for Value V (at namespace scope of a .cu file), and
/// the wavefront loop's in a build with it.
#define TESSERA_PIXEL_KERNEL(V) \
  TESSERA_WAVE_SLICE(V)         \
  template void tessera::cuda::launch_pixel_samples<V>(const tessera::cuda::SliceArgs&, unsigned, unsigned)
