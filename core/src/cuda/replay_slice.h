#pragma once
/// replay_slice: one slice of the pixel kernel over a distributed (paged) field on a device,
/// run until it reads no missing brick (device_bricks.h; docs/gpu.md, "Distributed fields on
/// the GPU"). Host half of the GPU backend, on any DeviceBackend.
#include <tessera/cuda_render.h>
#include <tessera/film.h>

#include "cuda/device_backend.h"
#include "cuda/device_bricks.h"
#include "kernel/stop_check.h"
#include "kernels/slice_args.h"

#include <string>

namespace tessera::cuda {

/// Device room to put a launch's lane sums and counters back before it runs again.
struct ReplayRoom {
  PixelSums* px;
  AuxSums* aux;  ///< null: no auxiliary sums
  unsigned long long* counters;
};

/// A distributed field's slice `a` (device_bricks.h): run, and while a lookup missed a brick,
/// its lanes' sums and counters restored, the noted bricks copied to the device and run
/// again. When the bricks it asks for do not fit the pool together it is split in halves
/// (pixels first, then samples; the halves in order, so each lane's samples are still added
/// in index order). `keep`: device room for the lane sums of jobs [a.j0, a.j1) and the
/// counters. Adds the launches run and those discarded to `launches` and `replays`. False
/// when the deadline stopped it (what ran is kept). Throws std::runtime_error when one
/// sample's bricks do not fit the pool (naming it), and what the backend or the bricks throw.
bool replay_slice(DeviceBackend& b, DeviceBricks& bricks, const KernelScene& dispatch, SliceArgs a,
                  const ReplayRoom& keep, const CudaLaunch& launch, StopCheck& stop, const std::string& name,
                  int& launches, int& replays);

}  // namespace tessera::cuda
