#pragma once
/// The CUDA DeviceBackend (device_backend.h), in a build with CUDA only: one per device index,
/// made on first use and kept for the process, its properties read once.
#include "cuda/device_backend.h"

#include <memory>

namespace tessera::cuda {

/// The backend of CUDA device `device` (a valid index: the caller checked the count). Throws
/// CudaError naming the call when the device's properties cannot be read.
std::shared_ptr<DeviceBackend> cuda_backend(int device);

}  // namespace tessera::cuda
