#pragma once
/// The host half of cuda_assemble_on_device (cuda_memory.h) for an emulated GPU (tests): the
/// checks, the replica in host memory declared the emulation's device memory (forgotten and
/// freed with its last owner), and the blocks placed on the host (a host block's bytes
/// counted as the GPU's copy would count them).
#include <tessera/copy_box.h>
#include <tessera/cuda_memory.h>
#include <tessera/memory_estimate.h>

#include "cuda/device_backend.h"
#include "cuda/emulated_device.h"

#include <memory>
#include <stdexcept>
#include <string>

namespace tessera::cuda {

/// The replica's bytes, checked: `blocks` and `offsets` alike in number, the limit.
inline std::size_t replica_bytes(std::size_t blocks, std::size_t offsets, const std::int64_t global[3], DType dtype,
                                 std::uint64_t limit_bytes, const std::string& limit_text) {
  if (blocks != offsets || blocks == 0)
    throw std::invalid_argument("cuda_assemble_on_device: " + std::to_string(blocks) + " blocks, " +
                                std::to_string(offsets) + " offsets");
  const auto bytes = static_cast<std::uint64_t>(global[0] * global[1] * global[2]) * dtype_size(dtype);
  if (bytes > limit_bytes)
    throw std::runtime_error("assembling the field's device blocks on the device needs " + format_bytes(bytes) +
                             ", more than " + limit_text);
  return static_cast<std::size_t>(bytes);
}

inline DeviceReplica assemble_emulated(const std::shared_ptr<DeviceBackend>& e, std::span<const FieldView> blocks,
                                       std::span<const std::array<std::int64_t, 3>> offsets,
                                       const std::int64_t global[3], DType dtype, std::uint64_t limit_bytes,
                                       const std::string& limit_text) {
  const std::size_t bytes = replica_bytes(blocks.size(), offsets.size(), global, dtype, limit_bytes, limit_text);
  bool any_device = false;
  std::uint64_t from_host = 0;
  for (const FieldView& b : blocks) {
    if (e->memory_kind(b.data) == MemoryKind::Host) {
      from_host += static_cast<std::uint64_t>(b.vertex_count()) * dtype_size(b.dtype);
      continue;
    }
    any_device = true;
    emulated_copy_out(*e, b.data, "cuda_assemble_on_device");
  }
  if (!any_device) throw std::invalid_argument("cuda_assemble_on_device: no block is device memory");
  auto* raw = static_cast<unsigned char*>(::operator new(bytes));
  emulated_declare_device_memory(*e, raw, bytes);
  std::shared_ptr<const void> memory(raw, [e](const void* p) {
    emulated_forget_device_memory(*e, p);
    ::operator delete(const_cast<void*>(p));
  });
  const FieldView dst = FieldView::contiguous(raw, dtype, global[0], global[1], global[2]);
  for (std::size_t n = 0; n < blocks.size(); ++n)
    copy_box(blocks[n],
             raw + offsets[n][0] * dst.byte_strides[0] + offsets[n][1] * dst.byte_strides[1] +
                 offsets[n][2] * dst.byte_strides[2],
             dst.byte_strides);
  return DeviceReplica{std::move(memory), dst, from_host};
}

}  // namespace tessera::cuda
