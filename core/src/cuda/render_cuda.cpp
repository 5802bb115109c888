/// The CUDA backend's entries (cuda_render.h) in a build with CUDA: the device count, where a
/// pointer's memory lives, and render_tiles_cuda, which checks the device and hands the work
/// to render_on_device (device_render.h) on that device's backend (cuda_backend.h). Every
/// CUDA call goes through cuda_check.
#include <tessera/cuda_render.h>

#include "cuda/cuda_backend.h"
#include "cuda/cuda_check.h"
#include "cuda/device_render.h"
#include "cuda/gpu_emulation.h"

#include <cuda_runtime_api.h>

#include <stdexcept>
#include <string>

namespace tessera {

using cuda::cuda_check;

bool cuda_built() { return true; }

int cuda_device_count(std::string* why) {
  if (cuda::gpu_emulation()) return 1;
  if (std::string disabled; cuda_disabled(&disabled)) {
    if (why) *why = "the GPU was disabled for the process by " + disabled;
    return 0;
  }
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) {
    if (why) *why = std::string("no CUDA device: ") + cudaGetErrorName(e) + " (" + cudaGetErrorString(e) + ")";
    cudaGetLastError();  // not sticky: clear it
    return 0;
  }
  if (n == 0 && why) *why = "no CUDA device is visible";
  return n;
}

MemoryKind cuda_memory_kind(const void* p) {
  if (const auto e = cuda::gpu_emulation()) return e->memory_kind(p);
  cuda::throw_if_disabled();
  if (p == nullptr) return MemoryKind::Host;
  cudaPointerAttributes attr{};
  const cudaError_t e = cudaPointerGetAttributes(&attr, p);
  if (e != cudaSuccess) {
    if (cuda::is_sticky(e)) cuda_check(e, "cudaPointerGetAttributes");
    cudaGetLastError();  // no driver, no device, or an old runtime's unregistered pointer: not sticky
    return MemoryKind::Host;
  }
  switch (attr.type) {
    case cudaMemoryTypeDevice: return MemoryKind::Device;
    case cudaMemoryTypeManaged: return MemoryKind::Managed;
    default: return MemoryKind::Host;  // unregistered or pinned host memory
  }
}

void render_tiles_cuda(const PreparedScene& scene, std::span<const int> tile_indices, Film& film, RenderStats& stats,
                       const CudaLaunch& launch, CudaTransfer* transfer) {
  if (const auto e = cuda::gpu_emulation())
    return cuda::render_tiles_emulated(e, scene, tile_indices, film, stats, launch, transfer);
  cuda::throw_if_disabled();
  std::string why;
  const int ndev = cuda_device_count(&why);
  if (ndev == 0) throw std::runtime_error("render_tiles_cuda: " + why);
  if (launch.device < 0 || launch.device >= ndev)
    throw std::invalid_argument("render_tiles_cuda: device " + std::to_string(launch.device) + " of " +
                                std::to_string(ndev) + " visible");
  cuda_check(cudaSetDevice(launch.device), "cudaSetDevice(" + std::to_string(launch.device) + ")");
  cuda::render_on_device(cuda::cuda_backend(launch.device), scene, tile_indices, film, stats, launch, transfer);
}

}  // namespace tessera
