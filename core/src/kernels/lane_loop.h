#pragma once
/// LaneLoop: how a thread of the GPU backend's pixel kernel (lane_kernel.h) walks through its
/// samples, the one the CUDA kernel is built with, and the deferred step loop's warp vote.
/// Host and device.
#include <tessera/host_device.h>

namespace tessera::cuda {

/// How a lane walks through its samples; all give the same sums, bit for bit (the same
/// operations of each sample, the samples ended in index order):
/// - PerSample: one sample's whole path, then the next (TileSampler::accumulate, as the CPU);
/// - Regenerate: one bounce per loop iteration, and a lane whose path has ended starts its
///   next sample in the next iteration, so that on a GPU a warp's threads run the same loop
///   body instead of waiting for the warp's longest path of each sample (path regeneration);
/// - Step: like Regenerate, one tracking step per loop iteration instead of one bounce
///   (PathSteps, kernel/path_steps.h), the code between walks run in the iteration whose
///   step ended the walk: threads in free flight and in shadow rays take their tentative
///   collisions together (the step-level loop).
/// - StepDefer: like Step, but a lane whose walk has ended runs the code between walks only
///   when at least half of its warp's active threads wait for it (a warp vote, lane_quorum),
///   so that this code, far longer than a tracking step, runs for many lanes at once.
/// - Wavefront: the step-level loop's pieces as two kernels in turn over lanes kept in device
///   memory (kernels/wave_kernel.h): one runs every lane's code between walks up to its next
///   walk and queues the lane, the other runs each queued lane's walk to its end, so a warp's
///   threads run one small loop together. Not for distributed (paged) fields, whose brick
///   misses are noted per thread of a launch: they keep Regenerate.
enum class LaneLoop : int { PerSample, Regenerate, Step, StepDefer, Wavefront };

/// The loop the CUDA kernel is compiled with (CMake: TESSERA_CUDA_PATH_REGEN,
/// TESSERA_CUDA_STEP_LOOP, TESSERA_CUDA_STEP_DEFER or TESSERA_CUDA_WAVEFRONT; none:
/// PerSample); the host emulation runs this one unless told otherwise (EmulatedDevice::lane_loop).
#if defined(TESSERA_CUDA_WAVEFRONT)
inline constexpr LaneLoop kDeviceLaneLoop = LaneLoop::Wavefront;
#elif defined(TESSERA_CUDA_STEP_DEFER)
inline constexpr LaneLoop kDeviceLaneLoop = LaneLoop::StepDefer;
#elif defined(TESSERA_CUDA_STEP_LOOP)
inline constexpr LaneLoop kDeviceLaneLoop = LaneLoop::Step;
#elif defined(TESSERA_CUDA_PATH_REGEN)
inline constexpr LaneLoop kDeviceLaneLoop = LaneLoop::Regenerate;
#else
inline constexpr LaneLoop kDeviceLaneLoop = LaneLoop::PerSample;
#endif

/// StepDefer's vote, called by every lane of the loop at each iteration `it`: whether a lane
/// that waits (`waiting`) runs the code between walks now. On the device: when at least half
/// of the warp's active threads wait. In the host emulation, whose lanes run one after the
/// other, a fixed pattern (two iterations of three) so that lanes also wait there. Any answer
/// gives the same sums: it only decides when a lane's code runs, never what it computes.
TESSERA_HOST_DEVICE inline bool lane_quorum(bool waiting, unsigned it) {
#if defined(__CUDA_ARCH__)
  const unsigned active = __activemask();
  return 2 * __popc(__ballot_sync(active, waiting)) >= __popc(active);
#else
  (void)waiting;
  return it % 3 != 2;
#endif
}

}  // namespace tessera::cuda
