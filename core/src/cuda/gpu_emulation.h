#pragma once
/// A testing seam: while a host emulation of a GPU (emulated_device.h) is installed, the
/// process's GPU entries (cuda_render.h, cuda_memory.h) use it instead of CUDA, in any build:
/// cuda_built() is true, cuda_device_count() is 1, cuda_memory_kind() is the emulation's (the
/// host ranges declared device memory), render_tiles_cuda renders on it (device 0), and
/// cuda_field_summary and cuda_copy_to_host read its "device memory" on the host. So the
/// adapter's device paths (the device choice, in place or staged, the bytes reported, ranks
/// under MPI) run in tests where no GPU is. For tests only: nothing else installs one.
#include "cuda/device_backend.h"

#include <memory>
#include <span>

namespace tessera::cuda {

/// Installs `b` for its lifetime (one at a time; the previous one back when it goes).
class ScopedGpuEmulation {
 public:
  explicit ScopedGpuEmulation(std::shared_ptr<DeviceBackend> b);
  ~ScopedGpuEmulation();
  ScopedGpuEmulation(const ScopedGpuEmulation&) = delete;
  ScopedGpuEmulation& operator=(const ScopedGpuEmulation&) = delete;

 private:
  std::shared_ptr<DeviceBackend> m_prev;
};

/// The installed emulation, or null (the entries then use CUDA, or say the build has none).
std::shared_ptr<DeviceBackend> gpu_emulation();

/// render_tiles_cuda on the installed emulation `b`: device 0 only.
void render_tiles_emulated(const std::shared_ptr<DeviceBackend>& b, const PreparedScene& scene,
                           std::span<const int> tile_indices, Film& film, RenderStats& stats, const CudaLaunch& launch,
                           CudaTransfer* transfer);

}  // namespace tessera::cuda
