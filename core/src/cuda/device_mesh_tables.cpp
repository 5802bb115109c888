/// DeviceMeshTables (device_mesh_tables.h): a layout's tables and its geometry's host arrays
/// copied to a device once.
#include "cuda/device_mesh_tables.h"

#include "mesh/mesh_layout.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <mutex>

namespace tessera::cuda {
namespace {

constexpr std::size_t kAlign = 256;

/// The four tables of a layout: host address and bytes, in allocation order.
struct Table {
  const void* src;
  std::size_t bytes;
  const char* what;
};

std::array<Table, 4> tables_of(const MeshLayout& layout) {
  const MeshFieldView v = layout.view(nullptr);
  const std::size_t n = layout.element_count();
  const auto loc = static_cast<std::size_t>(v.loc_n[0] * v.loc_n[1] * v.loc_n[2]);
  return {
      {{v.element, n * sizeof(MeshElementRef), "mesh elements"},
       {v.box, n * 6 * sizeof(double), "mesh element boxes"},
       {v.first, v.first ? (loc + 1) * sizeof(std::uint64_t) : 0, "mesh location cells"},
       {v.list, v.first ? static_cast<std::size_t>(v.first[loc]) * sizeof(std::uint32_t) : 0, "mesh location lists"}}};
}

std::size_t aligned(std::size_t b) { return (b + kAlign - 1) / kAlign * kAlign; }

}  // namespace

void MeshGeometryCopies::add_domain(const DomainAccess& a, std::vector<AddressSpan>& spans) {
  const unsigned char* reader[kSlots] = {a.x, a.y, a.z, a.conn};
  std::array<Slot, kSlots> s{};
  std::int64_t copied = 0;  // which slots are copied (the others are read in place)
  // The runs in the order of the first slot each holds, not by address: the key must not
  // depend on where the allocator put x, y and z this time
  std::vector<SpanRun> runs = merge_spans(spans);
  const auto first_tag = [&](const SpanRun& r) {
    int t = kSlots;
    for (std::size_t c = r.first; c < r.last; ++c) t = std::min(t, spans[c].tag);
    return t;
  };
  std::sort(runs.begin(), runs.end(), [&](const SpanRun& p, const SpanRun& q) { return first_tag(p) < first_tag(q); });
  for (const SpanRun& r : runs) {
    const auto run = static_cast<std::int32_t>(m_runs.size());
    const bool connectivity_only = r.last == r.first + 1 && spans[r.first].tag == 3;
    m_runs.push_back(
        {r.lo, static_cast<std::size_t>(r.hi - r.lo), connectivity_only ? "mesh connectivity" : "mesh coordinates"});
    m_key.push_back(r.hi - r.lo);
    for (std::size_t c = r.first; c < r.last; ++c) {
      const AddressSpan& sp = spans[c];
      s[static_cast<std::size_t>(sp.tag)] = {run, reader[sp.tag] - r.lo};
      copied |= std::int64_t{1} << sp.tag;
      // the reader's offset and its array's span in the run: what a kept copy must hold
      m_key.insert(m_key.end(), {sp.tag, run, reader[sp.tag] - r.lo, sp.lo - r.lo, sp.hi - sp.lo});
    }
  }
  // How the readers read the bytes (a kept copy of the same bytes read otherwise is refused)
  m_key.insert(m_key.end(), {copied, a.coord_stride, a.coord_f64 ? 1 : 0, a.index64 ? 1 : 0, a.nv,
                             static_cast<std::int64_t>(a.shape), a.dims[0], a.dims[1], a.dims[2], -1});
  m_slots.push_back(s);
}

std::uint64_t MeshGeometryCopies::bytes() const {
  std::uint64_t total = 0;
  for (const Run& r : m_runs) total += r.bytes;
  return total;
}

std::uint64_t DeviceMeshTables::bytes_of(const MeshLayout& layout, const MeshGeometryCopies& geometry) {
  std::uint64_t total = 0;
  for (const Table& t : tables_of(layout)) total += aligned(t.bytes == 0 ? 1 : t.bytes);
  for (const MeshGeometryCopies::Run& r : geometry.runs()) total += aligned(r.bytes == 0 ? 1 : r.bytes);
  return total;
}

bool DeviceMeshTables::kept(const MeshLayout& layout, const MeshGeometryCopies& geometry,
                            const DeviceBackend* backend) {
  MeshLayout::DeviceCopySlot& slot = layout.device_copy_slot();
  const std::lock_guard lock(slot.mutex);
  const auto* t = static_cast<const DeviceMeshTables*>(slot.copy.get());
  return t != nullptr && t->serves(backend, geometry.key());
}

std::shared_ptr<const DeviceMeshTables> DeviceMeshTables::of(const MeshLayout& layout,
                                                             const MeshGeometryCopies& geometry,
                                                             const std::shared_ptr<DeviceBackend>& backend,
                                                             std::uint64_t* copied) {
  MeshLayout::DeviceCopySlot& slot = layout.device_copy_slot();
  const std::lock_guard lock(slot.mutex);  // one copy made, however many renders ask at once
  auto kept = std::static_pointer_cast<const DeviceMeshTables>(slot.copy);
  if (kept && kept->serves(backend.get(), geometry.key())) return kept;
  auto made = std::make_shared<const DeviceMeshTables>(backend, layout, geometry);
  *copied += made->bytes();
  slot.copy = made;  // a copy on another backend, or of other arrays, is released with its last render
  return made;
}

DeviceMeshTables::DeviceMeshTables(std::shared_ptr<DeviceBackend> backend, const MeshLayout& layout,
                                   const MeshGeometryCopies& geometry)
    : m_backend(std::move(backend)), m_key(geometry.key()) {
  const std::array<Table, 4> tables = tables_of(layout);
  m_base = m_backend->allocate(bytes_of(layout, geometry), "mesh tables");
  auto* base = static_cast<unsigned char*>(m_base);
  std::size_t off = 0;
  const auto put = [&](const void* src, std::size_t bytes, const char* what) {
    unsigned char* at = base + off;
    if (bytes > 0) m_backend->copy_to_device(at, src, bytes, what);
    m_bytes += bytes;
    off += aligned(bytes == 0 ? 1 : bytes);
    return at;
  };
  std::array<const unsigned char*, 4> at{};
  try {
    for (std::size_t k = 0; k < tables.size(); ++k) at[k] = put(tables[k].src, tables[k].bytes, tables[k].what);
    for (const MeshGeometryCopies::Run& r : geometry.runs()) m_run.push_back(put(r.lo, r.bytes, r.what));
  } catch (...) {
    m_backend->release(m_base);
    throw;
  }
  element = reinterpret_cast<const MeshElementRef*>(at[0]);
  box = reinterpret_cast<const double*>(at[1]);
  first = reinterpret_cast<const std::uint64_t*>(at[2]);
  list = reinterpret_cast<const std::uint32_t*>(at[3]);
}

DeviceMeshTables::~DeviceMeshTables() { m_backend->release(m_base); }

}  // namespace tessera::cuda
