#pragma once
/// LaneLoop: how a thread of the GPU backend's pixel kernel (lane_kernel.h) walks through its
/// samples, and the one the CUDA kernel is built with. Plain data, host and device.

namespace tessera::cuda {

/// How a lane walks through its samples; both give the same sums, bit for bit (the same
/// operations of each sample, the samples ended in index order):
/// - PerSample: one sample's whole path, then the next (TileSampler::accumulate, as the CPU);
/// - Regenerate: one bounce per loop iteration, and a lane whose path has ended starts its
///   next sample in the next iteration, so that on a GPU a warp's threads run the same loop
///   body instead of waiting for the warp's longest path of each sample (path regeneration);
/// - Step: like Regenerate, one tracking step per loop iteration instead of one bounce
///   (PathSteps, kernel/path_steps.h), the code between walks run in the iteration whose
///   step ended the walk: threads in free flight and in shadow rays take their tentative
///   collisions together (the step-level loop).
enum class LaneLoop : int { PerSample, Regenerate, Step };

/// The loop the CUDA kernel is compiled with (CMake: TESSERA_CUDA_LANE_LOOP); the host
/// emulation runs this one unless told otherwise (EmulatedDevice::lane_loop).
#if defined(TESSERA_CUDA_STEP_LOOP)
inline constexpr LaneLoop kDeviceLaneLoop = LaneLoop::Step;
#elif defined(TESSERA_CUDA_PATH_REGEN)
inline constexpr LaneLoop kDeviceLaneLoop = LaneLoop::Regenerate;
#else
inline constexpr LaneLoop kDeviceLaneLoop = LaneLoop::PerSample;
#endif

}  // namespace tessera::cuda
