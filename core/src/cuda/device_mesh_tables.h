#pragma once
/// DeviceMeshTables: a mesh layout's tables (mesh/mesh_layout.h: each element's reference and
/// box, the location cells' starts and lists) in one allocation on one device, kept with the
/// layout (MeshLayout::device_copy_slot) so that the renders of later calls over the same
/// layout (a mesh promised or found unchanged) read them where they are instead of copying
/// them again. The layout is immutable, so a copy once made stays true. Made by DeviceScene
/// (device_scene.h) on any DeviceBackend (CUDA or the host emulation).
#include "cuda/device_backend.h"
#include "mesh/mesh_field_view.h"

#include <cstdint>
#include <memory>

namespace tessera {

class MeshLayout;

namespace cuda {

class DeviceMeshTables {
 public:
  /// Device bytes the tables of `layout` take (one allocation, each table 256-byte aligned).
  static std::uint64_t bytes_of(const MeshLayout& layout);
  /// Whether `layout` keeps a copy on `backend` now.
  static bool kept(const MeshLayout& layout, const DeviceBackend* backend);
  /// The tables of `layout` on `backend`: the kept copy when it is on that backend, else a new
  /// one (allocated and copied; *copied += the bytes copied), which the layout then keeps in
  /// place of any other. Throws what the backend throws (allocation, copy).
  static std::shared_ptr<const DeviceMeshTables> of(const MeshLayout& layout,
                                                    const std::shared_ptr<DeviceBackend>& backend,
                                                    std::uint64_t* copied);

  DeviceMeshTables(std::shared_ptr<DeviceBackend> backend, const MeshLayout& layout);
  ~DeviceMeshTables();
  DeviceMeshTables(const DeviceMeshTables&) = delete;
  DeviceMeshTables& operator=(const DeviceMeshTables&) = delete;

  const DeviceBackend* backend() const { return m_backend.get(); }
  std::uint64_t bytes() const { return m_bytes; }
  /// Device addresses of the tables (MeshFieldView's element, box, first, list)
  const MeshElementRef* element = nullptr;
  const double* box = nullptr;
  const std::uint64_t* first = nullptr;
  const std::uint32_t* list = nullptr;

 private:
  std::shared_ptr<DeviceBackend> m_backend;
  void* m_base = nullptr;
  std::uint64_t m_bytes = 0;
};

}  // namespace cuda
}  // namespace tessera
