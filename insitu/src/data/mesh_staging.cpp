// A mesh's device arrays staged to the host (mesh_staging.h).
#include "data/mesh_staging.h"

#include <tessera/cuda_memory.h>
#include <tessera/cuda_render.h>
#include <tessera/memory_estimate.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>

namespace tessera::insitu {
namespace {

/// One device array of a domain: its slot and bytes [lo, hi)
struct Piece {
  int slot;
  const unsigned char* lo;
  const unsigned char* hi;
};

/// The domain's device arrays, by address
std::vector<Piece> device_pieces(const MeshDomain& d, const std::array<char, kMeshArraySlots>& device) {
  std::vector<Piece> p;
  for (int s = 0; s < kMeshArraySlots; ++s) {
    const MeshArraySpan a = mesh_array(d, static_cast<MeshArraySlot>(s));
    if (!device[static_cast<std::size_t>(s)] || !a.data) continue;
    const auto* lo = static_cast<const unsigned char*>(a.data);
    p.push_back({s, lo, lo + a.bytes});
  }
  std::sort(p.begin(), p.end(), [](const Piece& a, const Piece& b) { return a.lo < b.lo; });
  return p;
}

/// Runs of pieces whose spans overlap or touch: [first, last) index ranges into `p`, each
/// with the run's byte span
struct Run {
  std::size_t first, last;
  const unsigned char* lo;
  const unsigned char* hi;
};
std::vector<Run> runs_of(const std::vector<Piece>& p) {
  std::vector<Run> r;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!r.empty() && p[i].lo <= r.back().hi) {
      r.back().last = i + 1;
      r.back().hi = std::max(r.back().hi, p[i].hi);
    } else {
      r.push_back({i, i + 1, p[i].lo, p[i].hi});
    }
  }
  return r;
}

}  // namespace

bool MeshMemory::on_device() const {
  for (const auto& d : device)
    for (const char c : d)
      if (c) return true;
  return false;
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
  for (std::size_t i = 0; i < m.domains.size(); ++i)
    for (const Run& r : runs_of(device_pieces(m.domains[i], where.device[i])))
      if (__builtin_add_overflow(total, static_cast<std::uint64_t>(r.hi - r.lo), &total)) total = UINT64_MAX;
  if (total == 0) return;
  if (total > limit_bytes)
    throw std::runtime_error("copying the mesh's device arrays to the host needs " + format_bytes(total) +
                             ", more than " + limit_text);
  for (std::size_t i = 0; i < m.domains.size(); ++i) {
    MeshDomain& d = m.domains[i];
    const std::vector<Piece> pieces = device_pieces(d, where.device[i]);
    for (const Run& r : runs_of(pieces)) {
      std::vector<unsigned char>& buf = out.buffers.emplace_back(static_cast<std::size_t>(r.hi - r.lo));
      cuda_copy_to_host(buf.data(), r.lo, buf.size(), stream);
      for (std::size_t k = r.first; k < r.last; ++k)
        set_mesh_array(d, static_cast<MeshArraySlot>(pieces[k].slot), buf.data() + (pieces[k].lo - r.lo));
      out.bytes += buf.size();
    }
  }
}

}  // namespace tessera::insitu
