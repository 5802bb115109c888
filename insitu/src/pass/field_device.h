#pragma once
/// Where a bound field renders: the device, whether the GPU reads it in place, the host
/// copies made of its device blocks (device_phase.h decides and makes them).
#include "data/device_arrays.h"

#include <tessera/config/device_choice.h>

namespace tessera::insitu {

struct FieldDevice {
  config::DeviceSelection selection;  ///< the render's device
  bool in_place = false;              ///< the GPU reads the simulation's device memory itself
  HostStaging staging;                ///< device blocks copied to the host for this render
};

}  // namespace tessera::insitu
