#pragma once
/// emulate_slice<V>: one slice of the pixel kernel (pixel_kernel.h) run on host threads, the
/// host emulation's launch (cuda/emulated_device.h): draw_lane (lane_kernel.h) for every thread
/// index of the slice, as the CUDA kernel runs it per GPU thread. Instantiated beside the
/// CPU's kernels of the same Value (kernels/tile_kernel_<value>.cpp), whose path tracer code
/// it shares, by TESSERA_INSTANTIATE_EMULATED_SLICE(V).
#include "kernels/lane_kernel.h"
#include "kernels/slice_args.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstdint>

namespace tessera::cuda {

/// `loop`: the lane loop to run (the CUDA kernel's is kDeviceLaneLoop).
template <class V>
void emulate_slice(const SliceArgs& a, LaneLoop loop);

#if defined(TESSERA_EMULATED_SLICE_DEFINITION)
template <class V>
void emulate_slice(const SliceArgs& a, LaneLoop loop) {
  const std::int64_t n = (a.j1 - a.j0) * a.lanes;
  if (n <= 0 || a.k1 <= a.k0) return;
  tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, n, 16), [&](const tbb::blocked_range<std::int64_t>& r) {
    unsigned long long sum[kCounterCount] = {};
    for (std::int64_t t = r.begin(); t < r.end(); ++t) {
      unsigned long long c[kCounterCount];
      const bool drawn = loop == LaneLoop::Regenerate  ? draw_lane<V, LaneLoop::Regenerate>(a, t, c)
                         : loop == LaneLoop::Step      ? draw_lane<V, LaneLoop::Step>(a, t, c)
                         : loop == LaneLoop::StepDefer ? draw_lane<V, LaneLoop::StepDefer>(a, t, c)
                                                       : draw_lane<V, LaneLoop::PerSample>(a, t, c);
      if (!drawn) continue;
      for (int i = 0; i < kCounterCount; ++i) sum[i] += c[i];
    }
    // Integer sums: the same in any order, as the kernel's atomicAdd
    for (int i = 0; i < kCounterCount; ++i) std::atomic_ref<unsigned long long>(a.counters[i]).fetch_add(sum[i]);
  });
}
#endif

}  // namespace tessera::cuda

/// Instantiates emulate_slice for Value V (in a kernels/tile_kernel_<value>.cpp file).
#define TESSERA_INSTANTIATE_EMULATED_SLICE(V) \
  template void tessera::cuda::emulate_slice<V>(const tessera::cuda::SliceArgs&, tessera::cuda::LaneLoop)
