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
  /// Several ranks on the GPU over a plain field with device blocks: the staging waits for the
  /// plan (stage_deferred): a distributed render reads those blocks where they are
  /// (FieldBlock::on_device), a replicated one stages them then.
  bool deferred = false;
  /// One rank on the GPU over a plain field cut into blocks of which some are device memory:
  /// the blocks are assembled on the device (cuda_assemble_on_device: the host blocks copied
  /// to their places), never staged, and the GPU reads that replica in place
  /// (FieldBlock::on_device for the range before it).
  bool assemble_on_device = false;
  BlocksMemory where;  ///< the blocks' memory, asked in the device phase (deferred: for the staging)
};

}  // namespace tessera::insitu
