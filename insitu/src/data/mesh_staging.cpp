// A mesh's device arrays staged to the host (mesh_staging.h).
#include "data/mesh_staging.h"

#include <tessera/byte_span.h>
#include <tessera/cuda_memory.h>
#include <tessera/cuda_render.h>
#include <tessera/memory_estimate.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>

namespace tessera::insitu {
namespace {

/// The domain's device arrays (tag: the slot)
std::vector<AddressSpan> device_spans(const MeshDomain& d, const std::array<char, kMeshArraySlots>& device) {
  std::vector<AddressSpan> p;
  for (int s = 0; s < kMeshArraySlots; ++s) {
    const MeshArraySpan a = mesh_array(d, static_cast<MeshArraySlot>(s));
    if (!device[static_cast<std::size_t>(s)] || !a.data) continue;
    const auto* lo = static_cast<const unsigned char*>(a.data);
    p.push_back({lo, lo + a.bytes, s});
  }
  return p;
}

}  // namespace

bool MeshMemory::on_device() const {
  for (const auto& d : device)
    for (const char c : d)
      if (c) return true;
  return false;
}

bool MeshMemory::all_device(const Mesh& m) const {
  if (device.size() != m.domains.size()) return false;
  for (std::size_t i = 0; i < m.domains.size(); ++i)
    for (int s = 0; s < kMeshArraySlots; ++s)
      if (mesh_array(m.domains[i], static_cast<MeshArraySlot>(s)).data && !device[i][static_cast<std::size_t>(s)])
        return false;
  return !m.domains.empty();
}

MeshMemory mesh_memory(const Mesh& m) {
  MeshMemory w;
  for (const MeshDomain& d : m.domains) {
    std::array<char, kMeshArraySlots> kinds{};
    for (int s = 0; s < kMeshArraySlots; ++s) {
      const MeshArraySpan a = mesh_array(d, static_cast<MeshArraySlot>(s));
      if (!a.data) continue;
      const MemoryKind k = cuda_memory_kind(a.data);
      kinds[static_cast<std::size_t>(s)] = k == MemoryKind::Device;
      w.gpu_readable |= k != MemoryKind::Host;
    }
    w.device.push_back(kinds);
  }
  return w;
}

void stage_mesh_to_host(Mesh& m, const MeshMemory& where, HostStaging& out, void* stream, std::uint64_t limit_bytes,
                        const std::string& limit_text) {
  if (where.device.size() != m.domains.size())
    throw std::logic_error("stage_mesh_to_host: the arrays' memory kinds are not this mesh's");
  // The bytes first, against the limit, before anything is allocated (each span fits int64:
  // the descriptors were checked; the sum saturates)
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < m.domains.size(); ++i) {
    std::vector<AddressSpan> spans = device_spans(m.domains[i], where.device[i]);
    for (const SpanRun& r : merge_spans(spans))
      if (__builtin_add_overflow(total, static_cast<std::uint64_t>(r.hi - r.lo), &total)) total = UINT64_MAX;
  }
  if (total == 0) return;
  if (total > limit_bytes)
    throw std::runtime_error("copying the mesh's device arrays to the host needs " + format_bytes(total) +
                             ", more than " + limit_text);
  for (std::size_t i = 0; i < m.domains.size(); ++i) {
    MeshDomain& d = m.domains[i];
    std::vector<AddressSpan> spans = device_spans(d, where.device[i]);
    for (const SpanRun& r : merge_spans(spans)) {
      std::vector<unsigned char>& buf = out.buffers.emplace_back(static_cast<std::size_t>(r.hi - r.lo));
      cuda_copy_to_host(buf.data(), r.lo, buf.size(), stream);
      for (std::size_t k = r.first; k < r.last; ++k) {
        // The host copy for the checks and tables; the original for a render on the GPU
        d.device_copy[spans[k].tag] = spans[k].lo;
        set_mesh_array(d, static_cast<MeshArraySlot>(spans[k].tag), buf.data() + (spans[k].lo - r.lo));
      }
      out.bytes += buf.size();
    }
  }
}

}  // namespace tessera::insitu
