/// The GPU emulation seam (gpu_emulation.h).
#include "cuda/gpu_emulation.h"

#include "cuda/device_render.h"

#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

namespace tessera::cuda {

namespace {
std::mutex g_mutex;  // guards g_installed
std::shared_ptr<DeviceBackend> g_installed;
}  // namespace

ScopedGpuEmulation::ScopedGpuEmulation(std::shared_ptr<DeviceBackend> b) {
  const std::lock_guard lock(g_mutex);
  m_prev = std::exchange(g_installed, std::move(b));
}

ScopedGpuEmulation::~ScopedGpuEmulation() {
  const std::lock_guard lock(g_mutex);
  g_installed = std::move(m_prev);
}

std::shared_ptr<DeviceBackend> gpu_emulation() {
  const std::lock_guard lock(g_mutex);
  return g_installed;
}

void render_tiles_emulated(const std::shared_ptr<DeviceBackend>& b, const PreparedScene& scene,
                           std::span<const int> tile_indices, Film& film, RenderStats& stats, const CudaLaunch& launch,
                           CudaTransfer* transfer) {
  if (launch.device != 0)
    throw std::invalid_argument("render_tiles_cuda: device " + std::to_string(launch.device) +
                                " of 1 visible (an emulated GPU)");
  render_on_device(b, scene, tile_indices, film, stats, launch, transfer);
}

}  // namespace tessera::cuda
