#pragma once
/// render_on_device: render_tiles_cuda's work (cuda_render.h says what it promises) on any
/// DeviceBackend (device_backend.h): checks what the device kernels cover, waits for the
/// caller's stream, finds or makes the prepared scene's device copies (device_scene.h) within
/// the memory limit and the device's free memory, copies the tiles' pixel sums to the device,
/// runs bounded slices with the deadline checked between them, merges the sample lanes and
/// copies the sums and counters back. The CUDA entry (render_cuda.cpp) and the host emulation
/// (emulated_device.h) both call it: one host half, tested without a GPU.
#include <tessera/cuda_render.h>

#include "cuda/device_backend.h"

#include <memory>
#include <span>

namespace tessera::cuda {

/// Throws as render_tiles_cuda does; `backend`'s device must be current.
void render_on_device(const std::shared_ptr<DeviceBackend>& backend, const PreparedScene& scene,
                      std::span<const int> tile_indices, Film& film, RenderStats& stats, const CudaLaunch& launch,
                      CudaTransfer* transfer);

}  // namespace tessera::cuda
