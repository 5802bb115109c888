#pragma once
/// The wavefront loop of the GPU backend (LaneLoop::Wavefront, lane_loop.h). A slice's lanes
/// (lane_kernel.h: thread t of the slice is lane t % lanes of job j0 + t / lanes) are drawn by
/// a bounded pool of path slots in device memory (WaveSlot), each slot taking the next lane
/// not yet taken when its lane's samples are done, and advanced in rounds of two kernels over
/// queues of slots, so that a warp's threads run the same small code together:
/// - wave_between, over the slots between walks: a slot runs its path's code between walks
///   (PathSteps::between: the camera ray, the emitters met, the collision, the light sample,
///   the next direction; a path that ended adds its sample and its lane starts its next, a
///   lane whose samples are drawn hands over its sums and the slot takes the next lane) up to
///   its next majorant walk, and joins the walk queue;
/// - wave_walk, over the slots in a walk (free flight or a shadow ray): at most `steps`
///   tracking steps each (field lookups only); a slot whose walk ended joins the next round's
///   between queue, the others its walk queue. A warp of walks thus runs `steps` steps, not
///   as long as its longest walk, and both kernels' warps are compacted queues.
/// Each lane's operations are the step-level loop's (PathSteps::advance) in the same order: the
/// same sums and counters, bit for bit, as the per-sample loop, whatever the slots' or the
/// queues' order, the pool's size or the steps per round. drive_wave runs the rounds. Host and
/// device code: the CUDA kernels (pixel_kernel_impl.cuh) run these bodies one per GPU thread,
/// the host emulation (emulated_slice.h) one per loop index.
#include <tessera/film.h>
#include <tessera/host_device.h>
#include <tessera/stats.h>

#include "kernels/lane_kernel.h"
#include "kernels/slice_args.h"
#include "kernels/tile_sampler.h"
#include "kernels/wave_scratch.h"

#include <cstddef>
#include <cstdint>
#include <type_traits>

#if !defined(__CUDA_ARCH__)
#include <atomic>
#endif

namespace tessera::cuda {

/// One path slot: the lane it draws (or none), that lane's path, sums and counts so far.
template <class V>
struct WaveSlot {
  typename TileSampler<V>::StepFlight f;
  PixelSums px;
  AuxSums aux;
  unsigned long long c[kCounterCount];
  std::int64_t t;  ///< the slice's thread (lane) this slot draws; -1: none yet
  int k;           ///< the lane's next sample index
};

/// Where a slice's scratch puts its parts (wave_scratch.h), and the rounds' parameters.
struct WaveArgs {
  SliceArgs a;
  WaveHeader* header;
  std::uint32_t* walks[2];     ///< by parity: slots in a walk
  std::uint32_t* betweens[2];  ///< by parity: slots between walks
  void* slots;
  std::int64_t nslots;
  std::int64_t threads;  ///< the slice's lanes: (j1 - j0) * lanes
  int steps;             ///< tracking steps a walk takes per round at most (>= 1)
};

/// Slice a's parts in its scratch (wave_scratch_bytes(threads of a, tuning.slots) bytes).
inline WaveArgs wave_args(const SliceArgs& a, const WaveTuning& tuning = {}) {
  WaveArgs w;
  w.a = a;
  w.threads = (a.j1 - a.j0) * a.lanes;
  w.nslots = wave_slot_count(w.threads, tuning.slots);
  w.steps = tuning.steps > 0 ? tuning.steps : 1;
  auto* base = static_cast<unsigned char*>(a.scratch);
  const std::size_t queue = wave_queue_bytes(w.nslots);
  w.header = reinterpret_cast<WaveHeader*>(base);
  for (int p = 0; p < 2; ++p) {
    w.walks[p] = reinterpret_cast<std::uint32_t*>(base + kWaveQueueOffset + (2 * p) * queue);
    w.betweens[p] = reinterpret_cast<std::uint32_t*>(base + kWaveQueueOffset + (2 * p + 1) * queue);
  }
  w.slots = base + kWaveQueueOffset + 4 * queue;
  return w;
}

namespace detail {

TESSERA_HOST_DEVICE inline unsigned long long fetch_add(unsigned long long* p, unsigned long long v) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(p, v);
#else
  return std::atomic_ref<unsigned long long>(*p).fetch_add(v, std::memory_order_relaxed);
#endif
}

template <class V>
TESSERA_HOST_DEVICE inline WaveSlot<V>* slot_at(const WaveArgs& w, std::int64_t i) {
  static_assert(sizeof(WaveSlot<V>) <= kWaveSlotBytes, "kWaveSlotBytes: a slot of this Value is larger");
  return reinterpret_cast<WaveSlot<V>*>(static_cast<unsigned char*>(w.slots) + i * kWaveSlotBytes);
}

}  // namespace detail

/// Slot i before the slice's first round: no lane yet, in the between queue of parity 0;
/// thread 0 sets the header (nothing else reads it in this kernel).
template <class V>
TESSERA_HOST_DEVICE inline void wave_begin(const WaveArgs& w, std::int64_t i) {
  WaveSlot<V> s;  // (every byte written: no later copy reads uninitialised memory)
  s.px = PixelSums{};
  s.aux = AuxSums{};
  for (int c = 0; c < kCounterCount; ++c) s.c[c] = 0;
  s.t = -1;
  s.k = 0;
  *detail::slot_at<V>(w, i) = s;
  w.betweens[0][i] = static_cast<std::uint32_t>(i);
  if (i == 0) {
    w.header->next_lane = 0;
    w.header->unused = 0;
    w.header->q[0] = {0, static_cast<unsigned long long>(w.nslots)};
    w.header->q[1] = {0, 0};
  }
}

/// True when Value V's slices may run the wavefront: not a distributed (paged) field, whose
/// brick misses are noted per thread of a launch (it keeps LaneLoop::Regenerate).
template <class V>
inline constexpr bool kWaveCapable = !std::is_same_v<typename ValueTraits<V>::base, PagedValue>;

/// Entry qi of the between queue of parity p (nothing past its count): the slot's code between
/// walks (see above), taking lanes until its path is in a walk (then in the walk queue of
/// parity p) or no lane is left (then in no queue).
template <class V>
TESSERA_HOST_DEVICE inline void wave_between(const WaveArgs& w, int p, std::int64_t qi) {
  if (static_cast<unsigned long long>(qi) >= w.header->q[p].betweens) return;
  const std::uint32_t i = w.betweens[p][qi];
  WaveSlot<V>* const slot = detail::slot_at<V>(w, i);
  const SliceArgs& a = w.a;
  const auto& medium = *static_cast<const GridMedium<V>*>(a.medium);
  WaveSlot<V> s = *slot;
  for (;;) {
    if (s.t < 0) {  // the next lane, its sums and counts
      const auto t = static_cast<std::int64_t>(detail::fetch_add(&w.header->next_lane, 1));
      if (t >= w.threads) break;
      const std::int64_t j = a.j0 + t / a.lanes;
      const std::int64_t q = j * a.lanes + t % a.lanes;
      s.t = t;
      s.k = first_sample(a, static_cast<int>(t % a.lanes));
      s.px = a.lane_px[q];
      s.aux = a.lane_aux ? a.lane_aux[q] : AuxSums{};
      s.f.live = false;
      for (int c = 0; c < kCounterCount; ++c) s.c[c] = 0;
    }
    const std::int64_t j = a.j0 + s.t / a.lanes;
    const int lane = static_cast<int>(s.t % a.lanes);
    const PixelJob job = a.jobs[j];
    TileSampler<V> ts(*a.ks, medium, job.culled == kJobCulled, nullptr);
    RenderStats st;
    AuxSums* const aux_p = a.lane_aux ? &s.aux : nullptr;
    const int first = first_sample(a, lane);
    bool walk = false;
    for (;;) {  // the lane's samples (draw_lane's step-level loop) up to a walk
      if (!s.f.live) {
        if (s.k >= a.k1 || (s.k != first && launch_missed(a))) break;
        ts.start(job.x, job.y, s.px, a.px[j].drawn + static_cast<std::uint64_t>(s.k), st, s.f);
        s.k += a.lanes;
        if (!s.f.live) {  // a culled tile's sample: its value is known
          ts.finish(s.f, s.px, aux_p, st);
          continue;
        }
      }
      if (ts.between(s.f)) {
        walk = true;
        break;
      }
      ts.finish(s.f, s.px, aux_p, st);
    }
    add_lane_counts(s.c, ts.counters(), st, job.culled != kJobNeighbour);
    if (walk) {
      *slot = s;
      w.walks[p][detail::fetch_add(&w.header->q[p].walks, 1)] = i;
      return;
    }
    // The lane's samples are drawn: its sums and counts out, then the next lane
    const std::int64_t q = j * a.lanes + lane;
    a.lane_px[q] = s.px;
    if (a.lane_aux) a.lane_aux[q] = s.aux;
    for (int c = 0; c < kCounterCount; ++c)
      if (s.c[c] != 0) detail::fetch_add(&a.counters[c], s.c[c]);
    s.t = -1;
  }
  *slot = s;
}

/// Entry qi of the walk queue of parity p (nothing past its count): at most w.steps tracking
/// steps of the slot's walk; then the slot is in a queue of parity 1 - p: between walks when
/// its walk ended, else in a walk.
template <class V>
TESSERA_HOST_DEVICE inline void wave_walk(const WaveArgs& w, int p, std::int64_t qi) {
  if (static_cast<unsigned long long>(qi) >= w.header->q[p].walks) return;
  const std::uint32_t i = w.walks[p][qi];
  const SliceArgs& a = w.a;
  WaveSlot<V>* const slot = detail::slot_at<V>(w, i);
  const PixelJob job = a.jobs[a.j0 + slot->t / a.lanes];
  TileSampler<V> ts(*a.ks, *static_cast<const GridMedium<V>*>(a.medium), job.culled == kJobCulled, nullptr);
  // (the walk's part of the path only: the rest stays where it is)
  typename PathSteps<V>::Walk walk = slot->f.path.w;
  Rng rng = slot->f.rng;
  bool ended = false;
  for (int n = 0; n < w.steps && !ended; ++n) ended = !ts.take_step(walk, rng);
  slot->f.path.w = walk;
  slot->f.rng = rng;
  unsigned long long c[kCounterCount];
  for (int k = 0; k < kCounterCount; ++k) c[k] = slot->c[k];
  add_lane_counts(c, ts.counters(), RenderStats{}, true);
  for (int k = 0; k < kCounterCount; ++k) slot->c[k] = c[k];
  WaveCounts& next = w.header->q[1 - p];
  if (ended) w.betweens[1 - p][detail::fetch_add(&next.betweens, 1)] = i;
  else w.walks[1 - p][detail::fetch_add(&next.walks, 1)] = i;
}

/// The rounds of one slice, `ops` running them on its device: ops.begin(nslots) (every slot's
/// wave_begin), ops.round(p) (the counts of parity 1 - p zeroed, then wave_between over the
/// between queue of parity p, then wave_walk over its walk queue), ops.pending(q) (the
/// counts of parity q, summed: read on the host). Every round advances every slot with work
/// (a walk by one step at least; the code between walks and a slot's lanes end: loop
/// guards), so the rounds are bounded by the lanes' walks; the counts are read every
/// kWaveRoundsPerCheck rounds, and a round with empty queues does nothing.
template <class Ops>
void drive_wave(const WaveArgs& w, Ops&& ops) {
  if (w.threads <= 0 || w.a.k1 <= w.a.k0) return;
  ops.begin(w.nslots);
  for (std::uint64_t r = 0;; ++r) {
    const int p = static_cast<int>(r & 1);
    ops.round(p);
    if (r % kWaveRoundsPerCheck == kWaveRoundsPerCheck - 1 && ops.pending(1 - p) == 0) return;
  }
}

}  // namespace tessera::cuda
