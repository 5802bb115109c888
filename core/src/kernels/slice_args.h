#pragma once
/// What one slice of the GPU backend's pixel kernel works on (a launch on a CUDA device, or a
/// host loop in the emulation, emulated_slice.h): the pixels, the counters, the
/// arguments. Plain data, host and device.
#include <tessera/film.h>

#include "kernel/kernel_scene.h"

#include <cstdint>

namespace tessera::cuda {

/// PixelJob::culled: the pixel is traced (its tile has something to trace) ...
inline constexpr int kJobTraced = 0;
/// ... its tile has nothing to trace (its pixels get the background) ...
inline constexpr int kJobCulled = 1;
/// ... or it is another tile's pixel whose adaptive-sampling pilot samples a block neighbour
/// needs (adaptive_plan.h): traced, its samples not counted in the samples drawn (the CPU's
/// TileSampler::draw of a pixel outside the tile; its lookups are counted).
inline constexpr int kJobNeighbour = 2;

/// One pixel of the call's tiles: where it is and its tile's culling verdict.
struct PixelJob {
  int x, y;
  int culled;  ///< kJobTraced, kJobCulled or kJobNeighbour
};

/// The counters the kernel adds up (RenderStats' fields of the same names).
enum Counter : int {
  kSamples,
  kFreeFlightLookups,
  kTransmittanceLookups,
  kGradientLookups,
  kRealCollisions,
  kNullCollisions,
  kDiscardedSamples,
  kStalledPaths,
  kCounterCount
};

/// One launch: the call's samples [k0, k1) of pixels [j0, j1) of `jobs`, each lane's into its
/// own sums. Every pointer is a device address.
struct SliceArgs {
  const KernelScene* ks;  ///< the scene, its pointers device addresses
  const void* medium;     ///< GridMedium<V> of the frame's Value (make_device_medium)
  const PixelJob* jobs;
  const PixelSums* px;           ///< per job: the sums before the call (drawn0)
  PixelSums* lane_px;            ///< per job and lane (job * lanes + lane)
  AuxSums* lane_aux;             ///< per job and lane, or null (no denoiser features)
  unsigned long long* counters;  ///< kCounterCount sums
  std::int64_t j0, j1;
  int k0, k1;
  int lanes;
};

}  // namespace tessera::cuda
