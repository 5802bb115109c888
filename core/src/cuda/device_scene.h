#pragma once
/// DeviceScene: the device copies of everything a prepared scene's KernelScene points to (the
/// field unless it is device or managed memory, majorants, empty-space reach, transfer
/// function, lights, background (an envmap's texels and sampling table), rectilinear axes'
/// coordinates and tables, refinement levels' tables and patches, a vector's components, a
/// curvilinear or unstructured mesh's tables and its domains' arrays, a distributed field's
/// brick pool), in
/// one device allocation, with the KernelScene and the medium over them, on a DeviceBackend
/// (device_backend.h: CUDA, or the host emulation). Made in two steps so that its size is
/// known before anything is allocated: the constructor plans (no allocation), upload()
/// allocates and copies.
/// Kept for a prepared scene's lifetime (PreparedSceneImpl::device_cache, render_cuda.cpp);
/// read-only once uploaded, so concurrent renders may share it.
#include "cuda/device_backend.h"
#include "cuda/device_bricks.h"
#include "cuda/device_mesh_tables.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

namespace tessera {

struct PreparedSceneImpl;
struct KernelScene;
class MeshLayout;

namespace cuda {

class DeviceScene {
 public:
  /// Plans the copies of `s` for `backend`'s device: what is host memory is to be copied,
  /// device or managed memory is read in place. `s` must outlive upload(). A distributed
  /// (paged) field gets a pool of brick slots (device_bricks.h): as many as the host's cache
  /// holds plus the bricks of the rank's own blocks, but no more than `budget` bytes of device
  /// memory leave room for beside the rest (0: no such bound), and at least one.
  DeviceScene(const PreparedSceneImpl& s, std::shared_ptr<DeviceBackend> backend, std::uint64_t budget = 0);
  ~DeviceScene();
  DeviceScene(const DeviceScene&) = delete;
  DeviceScene& operator=(const DeviceScene&) = delete;

  /// Device bytes the render reads: upload()'s allocation and a mesh's tables and geometry
  /// (kept with its layout between calls, device_mesh_tables.h).
  std::uint64_t bytes() const { return m_size + m_mesh_table_bytes; }
  /// Of bytes(), what upload() allocates now: the mesh's tables and geometry only when their
  /// layout keeps no copy of them on this device yet (as planned; one made meanwhile by another
  /// render is taken).
  std::uint64_t new_bytes() const { return m_size + (m_mesh_tables_kept ? 0 : m_mesh_table_bytes); }
  /// Allocates and copies; returns the bytes copied from the host. Once only.
  std::uint64_t upload();

  /// The backend the copies live on (a cache hit needs the same one).
  const DeviceBackend* backend() const { return m_backend.get(); }
  bool field_in_place() const { return m_field_in_place; }
  /// The uploaded KernelScene and medium (device addresses).
  const KernelScene* kernel() const;
  /// The host's KernelScene as the kernels see the field: a float32 field is widened to a
  /// float64 device copy (widen_field.h), so its kernel is the float64 one. For the launch's
  /// dispatch (launch_pixel_slice) only.
  const KernelScene& dispatch_scene() const { return *m_dispatch; }
  const void* medium() const;
  /// A distributed field's bricks on the device (null otherwise), with the mutex that its
  /// renders hold (the pool is the one mutable part of the copies).
  DeviceBricks* bricks() const { return m_bricks.get(); }
  std::mutex& bricks_mutex() const { return m_bricks_mutex; }

 private:
  /// A copy of `bytes` host bytes from `src` to the allocation's offset `offset`.
  struct Copy {
    const void* src;
    std::size_t bytes;
    std::size_t offset;
    const char* what;
  };
  std::size_t reserve(std::size_t bytes);
  std::size_t plan_copy(const void* src, std::size_t bytes, const char* what);
  /// A mesh: its elements, boxes and location lists and each domain's coordinates and
  /// connectivity (in the copy kept with the layout), and its values (in this allocation);
  /// each array read in place where it is device or managed memory
  void plan_mesh();

  const PreparedSceneImpl& m_scene;
  std::shared_ptr<DeviceBackend> m_backend;
  bool m_field_in_place = false;
  std::size_t m_size = 0;
  std::vector<Copy> m_copies;
  /// Pointer fix-ups run after allocation: each rewrites one pointer of the device KernelScene
  std::vector<std::function<void(unsigned char* base, KernelScene& d)>> m_fix;
  std::size_t m_off_kernel = 0, m_off_medium = 0, m_off_env = 0, m_off_lights = 0, m_off_patches = 0;
  std::size_t m_off_texels = 0, m_off_env_table = 0;  ///< an envmap's tables (unused otherwise)
  std::size_t m_medium_bytes = 0, m_npatches = 0;
  std::vector<std::pair<std::size_t, std::ptrdiff_t>> m_patch_data;  ///< per patch: offset, lowest byte offset
  void* m_base = nullptr;
  /// A mesh's domain readers (DomainAccess) on the device: per domain and array (x, y, z,
  /// connectivity, values; the MeshArraySlot order), the copy's offset in this allocation and
  /// the host address it starts at (offset SIZE_MAX: not copied here; the geometry's copies are
  /// in the kept copy, m_mesh_geometry), or the device copy the caller named
  static constexpr int kMeshSlots = 5;
  struct MeshArrays {
    std::size_t off[kMeshSlots] = {SIZE_MAX, SIZE_MAX, SIZE_MAX, SIZE_MAX, SIZE_MAX};
    const unsigned char* lo[kMeshSlots] = {};
    const unsigned char* in_place[kMeshSlots] = {};
  };
  std::vector<MeshArrays> m_mesh_arrays;
  /// A mesh's layout, the host arrays of its geometry to copy, the device bytes of both,
  /// whether the layout kept a copy of both here when planned, and the copy upload() took
  /// (held while this scene lives)
  const MeshLayout* m_mesh_layout = nullptr;
  MeshGeometryCopies m_mesh_geometry;
  std::uint64_t m_mesh_table_bytes = 0;
  bool m_mesh_tables_kept = false;
  std::shared_ptr<const DeviceMeshTables> m_mesh_tables;
  std::size_t m_off_domains = 0;
  /// A plain float32 field widened to float64 on the device: the copy's offset (else SIZE_MAX)
  std::size_t m_off_widened = SIZE_MAX;
  std::shared_ptr<KernelScene> m_dispatch;
  /// A distributed field: the bricks' part of the allocation and its slots
  std::size_t m_off_bricks = SIZE_MAX, m_brick_capacity = 0;
  std::uint64_t m_brick_threads = 0;
  std::unique_ptr<DeviceBricks> m_bricks;
  mutable std::mutex m_bricks_mutex;
};

}  // namespace cuda
}  // namespace tessera
