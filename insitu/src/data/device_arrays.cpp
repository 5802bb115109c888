// Device arrays: detection and staging to the host (device_arrays.h).
#include "data/device_arrays.h"

#include <tessera/byte_span.h>
#include <tessera/cuda_memory.h>
#include <tessera/cuda_render.h>
#include <tessera/memory_estimate.h>

#include <stdexcept>
#include <vector>

namespace tessera::insitu {

BlocksMemory blocks_memory(std::span<const FieldBlock> blocks) {
  BlocksMemory m;
  m.device.reserve(blocks.size());
  for (const FieldBlock& b : blocks) {
    const MemoryKind k = cuda_memory_kind(b.view.data);
    m.device.push_back(k == MemoryKind::Device);
    m.gpu_readable |= k != MemoryKind::Host;
  }
  return m;
}

void stage_blocks_to_host(FieldBinding& b, const BlocksMemory& where, HostStaging& out, void* stream,
                          std::uint64_t limit_bytes, const std::string& limit_text) {
  if (where.device.size() != b.blocks.size())
    throw std::logic_error("stage_blocks_to_host: the blocks' memory kinds are not this binding's");
  // The bytes first, against the limit, before anything is allocated
  const std::vector<char>& on_device = where.device;
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < b.blocks.size(); ++i)
    if (on_device[i]) total += static_cast<std::uint64_t>(byte_span(b.blocks[i].view).bytes());
  if (total == 0) return;
  if (b.staged_bytes + total > limit_bytes)
    throw std::runtime_error("copying the field's device arrays to the host needs " + format_bytes(total) +
                             (b.staged_bytes ? " (beside " + format_bytes(b.staged_bytes) + " staged already)" : "") +
                             ", more than " + limit_text);
  for (std::size_t i = 0; i < b.blocks.size(); ++i) {
    if (!on_device[i]) continue;
    FieldBlock& blk = b.blocks[i];
    const ByteSpan sp = byte_span(blk.view);
    std::vector<unsigned char>& buf = out.buffers.emplace_back(static_cast<std::size_t>(sp.bytes()));
    const auto* first = static_cast<const unsigned char*>(blk.view.data) + sp.lo;
    cuda_copy_to_host(buf.data(), first, buf.size(), stream);
    const void* moved = buf.data() - sp.lo;
    if (b.local.data == blk.view.data) b.local.data = moved;
    out.moved.emplace_back(moved, blk.view.data);
    blk.view.data = moved;
    out.bytes += buf.size();
  }
  b.staged_bytes += total;
}

}  // namespace tessera::insitu
