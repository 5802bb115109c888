#pragma once
/// Which device a render traces on: `tessera.device` and `tessera.cuda_device` (docs/gpu.md)
/// resolved against where the field lives and what this process can see.
#include <tessera/config/config.h>
#include <tessera/scene.h>

#include <string>

namespace tessera::config {

/// The device of one render and, on the GPU, its index.
struct DeviceSelection {
  Device device = Device::Cpu;
  int cuda_device = 0;  ///< a visible CUDA device (Device::Cuda)
};

/// Resolves the global options' device for a render whose field arrays are device (or
/// managed) memory when `data_on_device`; `local_rank` is the process's rank among the ranks
/// of its node (0 without MPI), for `cuda_device: -1`.
///   cpu   Device::Cpu;
///   auto  Device::Cuda when the data is on the device, Tessera has CUDA, a device is visible
///         and no earlier CUDA error disabled the GPU; Device::Cpu otherwise;
///   cuda  Device::Cuda, or std::runtime_error naming why not: a build without CUDA, no
///         visible device, the GPU disabled for the process (and by what), or a cuda_device
///         that is not one of the visible devices.
/// cuda_device -1 picks device local_rank modulo the visible devices (CUDA_VISIBLE_DEVICES
/// decides which those are). Cost: a device count query, no allocation on the device.
DeviceSelection resolve_device(const GlobalOptions& global, bool data_on_device, int local_rank);

/// "cpu", or "cuda:N" naming the device of `s`, for log lines and results.
std::string device_text(const DeviceSelection& s);

}  // namespace tessera::config
