#include <tessera/config/device_choice.h>

#include <tessera/cuda_render.h>

#include <stdexcept>
#include <string>

namespace tessera::config {

DeviceSelection resolve_device(const GlobalOptions& global, bool data_on_device, int local_rank) {
  DeviceSelection s;
  if (global.device == DeviceChoice::Cpu) return s;
  const bool required = global.device == DeviceChoice::Cuda;
  if (!required && !data_on_device) return s;
  const auto refuse = [&](const std::string& why) -> DeviceSelection {
    if (!required) return DeviceSelection{};
    throw std::runtime_error("tessera.device is cuda, but " + why);
  };
  if (!cuda_built()) return refuse("this Tessera was built without CUDA (configure with -DTESSERA_CUDA=ON)");
  std::string why;
  if (cuda_disabled(&why)) return refuse("the GPU was disabled for this process: " + why);
  const int count = cuda_device_count(&why);
  if (count <= 0) return refuse(why);
  if (global.cuda_device >= count)
    throw std::runtime_error("tessera.cuda_device is " + std::to_string(global.cuda_device) + ", but " +
                             std::to_string(count) + " CUDA device" + (count == 1 ? " is" : "s are") +
                             " visible (allowed: -1 or 0 to " + std::to_string(count - 1) + ")");
  s.device = Device::Cuda;
  s.cuda_device = global.cuda_device >= 0 ? global.cuda_device : (local_rank < 0 ? 0 : local_rank % count);
  return s;
}

std::string device_text(const DeviceSelection& s) {
  if (s.device == Device::Cpu) return "cpu";
  return "cuda:" + std::to_string(s.cuda_device);
}

}  // namespace tessera::config
