/// DeviceMeshTables (device_mesh_tables.h): a layout's tables copied to a device once.
#include "cuda/device_mesh_tables.h"

#include "mesh/mesh_layout.h"

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

std::uint64_t DeviceMeshTables::bytes_of(const MeshLayout& layout) {
  std::uint64_t total = 0;
  for (const Table& t : tables_of(layout)) total += aligned(t.bytes == 0 ? 1 : t.bytes);
  return total;
}

bool DeviceMeshTables::kept(const MeshLayout& layout, const DeviceBackend* backend) {
  MeshLayout::DeviceCopySlot& slot = layout.device_copy_slot();
  const std::lock_guard lock(slot.mutex);
  const auto* t = static_cast<const DeviceMeshTables*>(slot.copy.get());
  return t != nullptr && t->backend() == backend;
}

std::shared_ptr<const DeviceMeshTables> DeviceMeshTables::of(const MeshLayout& layout,
                                                             const std::shared_ptr<DeviceBackend>& backend,
                                                             std::uint64_t* copied) {
  MeshLayout::DeviceCopySlot& slot = layout.device_copy_slot();
  const std::lock_guard lock(slot.mutex);  // one copy made, however many renders ask at once
  auto kept = std::static_pointer_cast<const DeviceMeshTables>(slot.copy);
  if (kept && kept->backend() == backend.get()) return kept;
  auto made = std::make_shared<const DeviceMeshTables>(backend, layout);
  *copied += made->bytes();
  slot.copy = made;  // a copy on another backend is released with its last render
  return made;
}

DeviceMeshTables::DeviceMeshTables(std::shared_ptr<DeviceBackend> backend, const MeshLayout& layout)
    : m_backend(std::move(backend)) {
  const std::array<Table, 4> tables = tables_of(layout);
  const std::size_t size = bytes_of(layout);
  m_base = m_backend->allocate(size, "mesh tables");
  auto* base = static_cast<unsigned char*>(m_base);
  std::size_t off = 0;
  std::array<const unsigned char*, 4> at{};
  try {
    for (std::size_t k = 0; k < tables.size(); ++k) {
      at[k] = base + off;
      if (tables[k].bytes > 0) m_backend->copy_to_device(base + off, tables[k].src, tables[k].bytes, tables[k].what);
      m_bytes += tables[k].bytes;
      off += aligned(tables[k].bytes == 0 ? 1 : tables[k].bytes);
    }
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
