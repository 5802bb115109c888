#pragma once
/// The host emulation of a GPU: a DeviceBackend (device_backend.h) whose "device memory" is
/// host memory and whose kernels run their per-thread bodies (lane_kernel.h) on host threads,
/// in every build. render_on_device (device_render.h) on it runs the GPU backend's whole host
/// half (the scene's device copies, the float32 widening, slicing, lanes, merging, limits,
/// counters) and the kernel's per-thread code, so CI tests them without a GPU: a slip in a
/// device copy or a lane shows as a counter or image that differs from the CPU's. What it
/// cannot show is the device compiler's code (docs/gpu.md).
///
/// Emulated allocations are filled with a byte pattern (as uninitialised device memory holds
/// garbage), and host ranges can be declared device memory, read in place as the CUDA
/// backend reads a simulation's device arrays. It also covers what the CUDA kernels do not
/// yet hold: refinement levels.
#include "cuda/device_backend.h"
#include "kernels/lane_loop.h"
#include "kernels/wave_scratch.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace tessera::cuda {

struct EmulatedDevice {
  std::string name = "host emulation";
  /// Total device memory; free is this less what the emulated device holds.
  std::size_t memory_bytes = std::size_t{1} << 40;
  /// Host ranges [p, p + bytes) the device takes for its own memory (MemoryKind::Device).
  std::vector<std::pair<const void*, std::size_t>> device_ranges;
  /// The lanes' loop the emulated kernel runs: by default the CUDA kernel's.
  LaneLoop lane_loop = kDeviceLaneLoop;
  /// The wavefront loop's sizes (wave_scratch.h; by default a GPU's): a test takes fewer
  /// slots than a slice's lanes, so that each slot draws several lanes, and few steps per round.
  WaveTuning wave;
  /// Called after each slice the backend runs, with the count of slices so far (a test's hook:
  /// e.g. to wait out a deadline at a chosen point of a render). Null: nothing.
  std::function<void(std::int64_t slices)> after_slice;
  /// Called before a copy out of device memory reads `src` (`what`: cuda_copy_box_to_host,
  /// or the device summaries' cuda_field_summary and cuda_field_summary_accumulate); true: the
  /// copy fails with a std::runtime_error, as a CUDA copy from a freed array would (a test's
  /// hook). Null: nothing fails.
  std::function<bool(const void* src, const std::string& what)> copy_out_fault;
};

/// A backend emulating `d`. A prepared scene's device copies are kept per backend object, so
/// keep one to see them reused.
std::shared_ptr<DeviceBackend> emulated_backend(EmulatedDevice d = {});

/// Bytes an emulated backend holds now (every allocation not yet released).
std::size_t emulated_bytes_held(const DeviceBackend& b);

/// Declares host range [p, p + bytes) device memory of emulated backend `b`, as a simulation's
/// cudaMalloc'd array would be, until forgotten (by its start p). Thread-safe.
void emulated_declare_device_memory(DeviceBackend& b, const void* p, std::size_t bytes);
void emulated_forget_device_memory(DeviceBackend& b, const void* p);

/// Throws std::runtime_error naming `what` when emulated backend `b`'s copy_out_fault says a
/// copy out of device memory from `src` fails.
void emulated_copy_out(const DeviceBackend& b, const void* src, const char* what);

}  // namespace tessera::cuda
