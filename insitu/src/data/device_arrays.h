#pragma once
/// A simulation's arrays in GPU memory (docs/gpu.md): which blocks are device memory, and
/// their staging to the host when a render cannot read them in place (several ranks or
/// blocks assembled into a replica, refinement levels, a vector's magnitude, a render on the
/// CPU). Managed memory is readable on the host as it is and is never staged.
#include "data/field_binding.h"

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace tessera::insitu {

/// Where a field's blocks live, from one question to the CUDA runtime per block (asked once:
/// the answers are carried to the staging below).
struct BlocksMemory {
  bool gpu_readable = false;  ///< some block is device or managed memory: a render may read it in place on the GPU
  std::vector<char> device;   ///< per block, in order: 1 where it is device memory
  /// Some block is device memory (cudaMemoryTypeDevice; not managed).
  bool on_device() const {
    for (const char d : device)
      if (d) return true;
    return false;
  }
};
BlocksMemory blocks_memory(std::span<const FieldBlock> blocks);

/// The host copies of staged blocks, kept while the render reads them.
struct HostStaging {
  std::vector<std::vector<unsigned char>> buffers;
  std::uint64_t bytes = 0;  ///< copied device -> host
  /// Per staged block: the view's data as staged (host) and as it was (device)
  std::vector<std::pair<const void*, const void*>> moved;

  /// The device address whose host copy `host_data` (a staged view's data) is; null when it
  /// is not one.
  const void* device_original(const void* host_data) const {
    for (const auto& [to, from] : moved)
      if (to == host_data && host_data != nullptr) return from;
    return nullptr;
  }
};

/// Copies each device-memory block of `b` (`where`: blocks_memory(b.blocks), asked before b's
/// views changed; its whole strided span, ghost cells skipped by the view as before) to a host
/// buffer and points the block's view, and `b.local` where it is that block, at the copy:
/// afterwards nothing of `b` is device memory. The copies are
/// checked against `limit_bytes` (with b.staged_bytes already counted) before any is made:
/// over it, std::runtime_error naming the bytes and `limit_text`; CUDA failures throw as
/// cuda_copy_to_host does. `stream`: the simulation's CUDA stream (null: the whole device).
void stage_blocks_to_host(FieldBinding& b, const BlocksMemory& where, HostStaging& out, void* stream,
                          std::uint64_t limit_bytes, const std::string& limit_text);

}  // namespace tessera::insitu
