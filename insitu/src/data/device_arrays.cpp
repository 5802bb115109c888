// Device arrays: detection and staging to the host (device_arrays.h).
#include "data/device_arrays.h"

#include <tessera/cuda_memory.h>
#include <tessera/cuda_render.h>
#include <tessera/memory_estimate.h>

#include <stdexcept>

namespace tessera::insitu {
namespace {

/// Offsets of the first byte and one past the last byte of a strided view from its data
/// pointer (negative strides reach below it).
void view_span(const FieldView& v, std::int64_t* lo, std::int64_t* hi) {
  *lo = 0;
  *hi = static_cast<std::int64_t>(dtype_size(v.dtype));
  for (int a = 0; a < 3; ++a) {
    const std::int64_t reach = (v.dims[a] - 1) * v.byte_strides[a];
    if (reach < 0) *lo += reach;
    else *hi += reach;
  }
}

}  // namespace

bool blocks_on_device(std::span<const FieldBlock> blocks) {
  for (const FieldBlock& b : blocks)
    if (cuda_memory_kind(b.view.data) == MemoryKind::Device) return true;
  return false;
}

bool blocks_gpu_readable(std::span<const FieldBlock> blocks) {
  for (const FieldBlock& b : blocks)
    if (cuda_memory_kind(b.view.data) != MemoryKind::Host) return true;
  return false;
}

void stage_blocks_to_host(FieldBinding& b, HostStaging& out, void* stream, std::uint64_t limit_bytes,
                          const std::string& limit_text) {
  // The bytes first, against the limit, before anything is allocated
  std::uint64_t total = 0;
  for (const FieldBlock& blk : b.blocks) {
    if (cuda_memory_kind(blk.view.data) != MemoryKind::Device) continue;
    std::int64_t lo, hi;
    view_span(blk.view, &lo, &hi);
    total += static_cast<std::uint64_t>(hi - lo);
  }
  if (total == 0) return;
  if (b.staged_bytes + total > limit_bytes)
    throw std::runtime_error("copying the field's device arrays to the host needs " + format_bytes(total) +
                             (b.staged_bytes ? " (beside " + format_bytes(b.staged_bytes) + " staged already)" : "") +
                             ", more than " + limit_text);
  for (FieldBlock& blk : b.blocks) {
    if (cuda_memory_kind(blk.view.data) != MemoryKind::Device) continue;
    std::int64_t lo, hi;
    view_span(blk.view, &lo, &hi);
    std::vector<unsigned char>& buf = out.buffers.emplace_back(static_cast<std::size_t>(hi - lo));
    const auto* first = static_cast<const unsigned char*>(blk.view.data) + lo;
    cuda_copy_to_host(buf.data(), first, buf.size(), stream);
    const void* moved = buf.data() - lo;
    if (b.local.data == blk.view.data) b.local.data = moved;
    blk.view.data = moved;
    out.bytes += buf.size();
  }
  b.staged_bytes += total;
}

}  // namespace tessera::insitu
