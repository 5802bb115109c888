#pragma once
/// What one slice of the GPU backend's pixel kernel works on (a launch on a CUDA device, or a
/// host loop in the emulation, emulated_slice.h): the pixels, the counters, the
/// arguments. Plain data, host and device.
#include <tessera/device_brick_table.h>
#include <tessera/film.h>

#include "kernel/kernel_scene.h"

#include <atomic>
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
  /// A distributed field's bricks noted missing in this launch (DeviceBrickTable::count), or
  /// null: once nonzero the launch is to be run again, so each lane stops after its sample
  const unsigned long long* missed = nullptr;
  /// Per thread: its sample has missed a brick (DeviceBrickTable::path_missed), or null
  unsigned char* path_missed = nullptr;
  /// The wavefront loop's path slots and queue (kernels/wave_kernel.h: wave_scratch_bytes of
  /// the slice's threads), or null when the backend's loop needs none
  void* scratch = nullptr;
};

/// True once a lookup of this launch missed a brick (a.missed set and nonzero). Any thread.
TESSERA_HOST_DEVICE inline bool launch_missed(const SliceArgs& a) {
  if (!a.missed) return false;
#if defined(__CUDA_ARCH__)
  return *static_cast<volatile const unsigned long long*>(a.missed) != 0;
#else
  return std::atomic_ref<unsigned long long>(*const_cast<unsigned long long*>(a.missed))
             .load(std::memory_order_relaxed) != 0;
#endif
}

}  // namespace tessera::cuda
