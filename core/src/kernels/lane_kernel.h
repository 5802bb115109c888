#pragma once
/// The per-thread bodies of the device backend's two kernels, host and device code from one
/// source: the CUDA kernels (pixel_kernel_impl.cuh, merge_lanes.cu) run them one per GPU
/// thread, the host emulation (cuda/emulated_device.h, emulated_slice.h) one per loop index. Everything the backend
/// computes per pixel is here, so the emulation in CI checks the same arithmetic and order.
#include <tessera/film.h>
#include <tessera/host_device.h>
#include <tessera/stats.h>

#include "kernels/lane_loop.h"
#include "kernels/slice_args.h"
#include "kernels/tile_sampler.h"

#include <cstdint>
#include <type_traits>

namespace tessera::cuda {

/// The first of lane `lane`'s samples in slice `a`: the least k in [k0, ...) with k = lane
/// (mod lanes); the lane's samples are then k, k + lanes, ... below k1.
TESSERA_HOST_DEVICE inline int first_sample(const SliceArgs& a, int lane) {
  return a.k0 + ((lane - a.k0 % a.lanes) % a.lanes + a.lanes) % a.lanes;
}

/// Adds a tracer's counts `k` and the samples of `st` to the launch counters' order in c
/// (`counted` false: a neighbour's pilot, whose samples are not the image's; its lookups count).
TESSERA_HOST_DEVICE inline void add_lane_counts(unsigned long long c[kCounterCount], const KernelCounters& k,
                                                const RenderStats& st, bool counted) {
  c[kSamples] += counted ? st.samples : 0;
  c[kDiscardedSamples] += counted ? st.discarded_samples : 0;
  c[kFreeFlightLookups] += k.free_flight_lookups;
  c[kTransmittanceLookups] += k.transmittance_lookups;
  c[kGradientLookups] += k.gradient_lookups;
  c[kRealCollisions] += k.real_collisions;
  c[kNullCollisions] += k.null_collisions;
  c[kStalledPaths] += k.stalled_paths;
}

/// Thread t of slice `a` (pixel_kernel.h): lane t % lanes of job j0 + t / lanes (a pixel's
/// lanes side by side, so their rays run together) draws its samples of [k0, k1) in index
/// order into its own sums. Its counters go to c[kCounterCount] (the caller adds them to the
/// slice's: integer sums, the same in any order). False, c untouched, when t is past the slice.
template <class V, LaneLoop L = kDeviceLaneLoop>
TESSERA_HOST_DEVICE inline bool draw_lane(const SliceArgs& a, std::int64_t t, unsigned long long c[kCounterCount]) {
  const std::int64_t j = a.j0 + t / a.lanes;
  if (j >= a.j1) return false;
  const int lane = static_cast<int>(t % a.lanes);
  const PixelJob job = a.jobs[j];
  TileSampler<V> ts(*a.ks, *static_cast<const GridMedium<V>*>(a.medium), job.culled == kJobCulled, nullptr);
  const std::uint64_t drawn0 = a.px[j].drawn;
  const std::int64_t q = j * a.lanes + lane;
  PixelSums px = a.lane_px[q];
  AuxSums aux;
  if (a.lane_aux) aux = a.lane_aux[q];
  RenderStats st;
  // The CPU's estimator (sample_uniform, tile_kernel_impl.h) for this lane's samples, in index
  // order: k = lane (mod lanes) within [k0, k1)
  const int first = first_sample(a, lane);
  AuxSums* const aux_p = a.lane_aux ? &aux : nullptr;
  if constexpr (L == LaneLoop::PerSample) {
    // (a launch that missed a brick is run again: each lane ends it after its sample, so that
    // every lane's path still asks for its bricks)
    for (int k = first; k < a.k1; k += a.lanes) {
      begin_brick_sample(a.path_missed, t);
      ts.accumulate(job.x, job.y, px, aux_p, drawn0 + static_cast<std::uint64_t>(k), st);
      if (launch_missed(a)) break;
    }
  } else {
    // A lane whose path has ended starts its next sample at the next iteration
    using F = std::conditional_t<L == LaneLoop::Regenerate, typename TileSampler<V>::Flight,
                                 typename TileSampler<V>::StepFlight>;
    F f;
    int k = first;
    for (unsigned it = 0;; ++it) {
      if (!f.live) {
        if (k >= a.k1 || (k != first && launch_missed(a))) break;
        begin_brick_sample(a.path_missed, t);
        ts.start(job.x, job.y, px, drawn0 + static_cast<std::uint64_t>(k), st, f);
        k += a.lanes;
        if (!f.live) {  // a culled tile's sample: its value is known
          ts.finish(f, px, aux_p, st);
          continue;
        }
      }
      if constexpr (L == LaneLoop::StepDefer) {
        // Lanes in a walk step; a lane between walks runs that code when the warp's vote says
        // so (every lane votes at every iteration, whatever it does then)
        const bool waiting = !TileSampler<V>::walking(f);
        const bool go = lane_quorum(waiting, it);
        if (!waiting) ts.take_step(f);
        else if (go && !ts.between(f)) ts.finish(f, px, aux_p, st);
      } else if (!ts.step(f)) {
        ts.finish(f, px, aux_p, st);
      }
    }
  }
  a.lane_px[q] = px;
  if (a.lane_aux) a.lane_aux[q] = aux;
  for (int i = 0; i < kCounterCount; ++i) c[i] = 0;
  add_lane_counts(c, ts.counters(), st, job.culled != kJobNeighbour);
  return true;
}

/// `from` added to `to`, field by field.
TESSERA_HOST_DEVICE inline void add_sums(PixelSums& to, const PixelSums& from) {
  to.r += from.r;
  to.g += from.g;
  to.b += from.b;
  to.a += from.a;
  to.lum += from.lum;
  to.lum2 += from.lum2;
  to.n += from.n;
  to.drawn += from.drawn;
}
TESSERA_HOST_DEVICE inline void add_sums(AuxSums& to, const AuxSums& from) {
  for (int c = 0; c < 3; ++c) {
    to.albedo[c] += from.albedo[c];
    to.normal[c] += from.normal[c];
  }
}

/// Job j's lane sums added to its pixel sums (and auxiliary sums when given) in lane order.
TESSERA_HOST_DEVICE inline void merge_pixel(PixelSums* px, AuxSums* aux, const PixelSums* lane_px,
                                            const AuxSums* lane_aux, std::int64_t j, int lanes) {
  PixelSums p = px[j];
  for (int l = 0; l < lanes; ++l) add_sums(p, lane_px[j * lanes + l]);
  px[j] = p;
  if (!aux) return;
  AuxSums x = aux[j];
  for (int l = 0; l < lanes; ++l) add_sums(x, lane_aux[j * lanes + l]);
  aux[j] = x;
}

}  // namespace tessera::cuda
