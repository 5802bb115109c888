#pragma once
/// emulate_slice<V>: one slice of the pixel kernel (pixel_kernel.h) run on host threads, the
/// host emulation's launch (cuda/emulated_device.h): draw_lane (lane_kernel.h) for every thread
/// index of the slice, as the CUDA kernel runs it per GPU thread. Instantiated beside the
/// CPU's kernels of the same Value (kernels/tile_kernel_<value>.cpp), whose path tracer code
/// it shares, by TESSERA_INSTANTIATE_EMULATED_SLICE(V).
#include "kernels/lane_kernel.h"
#include "kernels/slice_args.h"
#include "kernels/wave_kernel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstdint>
#include <stdexcept>

namespace tessera::cuda {

/// `loop`: the lane loop to run (the CUDA kernel's is kDeviceLaneLoop); `wave`: the
/// wavefront's sizes (its scratch: wave_scratch_bytes with wave.slots).
template <class V>
void emulate_slice(const SliceArgs& a, LaneLoop loop, const WaveTuning& wave);

#if defined(TESSERA_EMULATED_SLICE_DEFINITION)
/// The wavefront's rounds (wave_kernel.h) over a slice, its kernels as host loops over the
/// queues' counts; a queue fills in whatever order the threads reach it, as on a GPU.
template <class V>
void emulate_wave(const WaveArgs& w) {
  const auto each = [](unsigned long long n, auto&& body) {
    tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, static_cast<std::int64_t>(n), 16),
                      [&](const tbb::blocked_range<std::int64_t>& r) {
                        for (std::int64_t i = r.begin(); i < r.end(); ++i) body(i);
                      });
  };
  struct Ops {
    const WaveArgs& w;
    decltype(each)& for_each;
    void begin(std::int64_t n) {
      for_each(static_cast<unsigned long long>(n), [&](std::int64_t i) { wave_begin<V>(w, i); });
    }
    void round(int p) {
      w.header->q[1 - p] = {0, 0};
      for_each(w.header->q[p].betweens, [&](std::int64_t i) { wave_between<V>(w, p, i); });
      for_each(w.header->q[p].walks, [&](std::int64_t i) { wave_walk<V>(w, p, i); });
    }
    unsigned long long pending(int q) const { return w.header->q[q].walks + w.header->q[q].betweens; }
  };
  drive_wave(w, Ops{w, each});
}

template <class V>
void emulate_slice(const SliceArgs& a, LaneLoop loop, const WaveTuning& wave) {
  const std::int64_t n = (a.j1 - a.j0) * a.lanes;
  if (n <= 0 || a.k1 <= a.k0) return;
  if (loop == LaneLoop::Wavefront) {
    if constexpr (kWaveCapable<V>) {
      if (!a.scratch) throw std::logic_error("emulated wavefront slice without its path slots (SliceArgs::scratch)");
      emulate_wave<V>(wave_args(a, wave));
      return;
    }
    loop = LaneLoop::Regenerate;
  }
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
#define TESSERA_INSTANTIATE_EMULATED_SLICE(V)                                                             \
  template void tessera::cuda::emulate_slice<V>(const tessera::cuda::SliceArgs&, tessera::cuda::LaneLoop, \
                                                const tessera::cuda::WaveTuning&)
