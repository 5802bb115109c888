#pragma once
/// DeviceMeshTables: what a mesh keeps on one device between calls, in one allocation: its
/// layout's tables (mesh/mesh_layout.h: each element's reference and box, the location cells'
/// starts and lists) and the host arrays of its geometry that a render copies (each domain's
/// x, y, z and connectivity, MeshGeometryCopies). Kept with the layout
/// (MeshLayout::device_copy_slot) so that the renders of later calls over the same layout (a
/// mesh promised or found unchanged, or several ranks' geometry from the last full exchange)
/// read them where they are and copy only the values.
///
/// The layout is immutable, so its tables once copied stay true. The geometry is the one the
/// layout was built over whenever a render uses the layout (reused only when promised
/// unchanged, found the same by its hash, or read from the kept exchange), so its copy stays
/// true as long as the arrays are laid out the same: a copy serves a render only when the
/// render's geometry arrays have the same key (runs, offsets, spans, strides, dtypes, shapes;
/// never host addresses). A broken tessera_mesh_unchanged promise then draws the geometry the
/// layout was built over, and still reads nothing outside the copies. Made by DeviceScene
/// (device_scene.h) on any DeviceBackend (CUDA or the host emulation).
#include "cuda/device_backend.h"
#include "mesh/domain_access.h"
#include "mesh/mesh_field_view.h"

#include <tessera/byte_span.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace tessera {

class MeshLayout;

namespace cuda {

/// The host arrays of a mesh's geometry that a device render copies: per domain the spans of
/// its x, y, z and connectivity (MeshArraySlot 0-3) that are host memory with no device copy
/// named, merged where they overlap or touch (one run per interleaved array), and where each
/// domain reader's pointer lies in them.
class MeshGeometryCopies {
 public:
  static constexpr int kSlots = 4;
  /// Where one reader's pointer lies: in run `run` (-1: not copied, read in place) at `offset`
  /// bytes from its start.
  struct Slot {
    std::int32_t run = -1;
    std::int64_t offset = 0;
  };
  struct Run {
    const unsigned char* lo = nullptr;
    std::size_t bytes = 0;
    const char* what = "";  ///< for messages: "mesh coordinates" or "mesh connectivity"
  };

  /// Adds the next domain: `a` its reader, `spans` its geometry arrays to copy (tags: slots
  /// 0-3; sorted by merge_spans here).
  void add_domain(const DomainAccess& a, std::vector<AddressSpan>& spans);

  const std::vector<Run>& runs() const { return m_runs; }
  /// Per domain, in order, its four slots.
  const std::vector<std::array<Slot, kSlots>>& slots() const { return m_slots; }
  /// What a kept copy must match to serve (equal keys: the same runs' sizes, readers' offsets,
  /// spans, strides, dtypes and shapes, domain by domain).
  const std::vector<std::int64_t>& key() const { return m_key; }
  std::uint64_t bytes() const;

 private:
  std::vector<Run> m_runs;
  std::vector<std::array<Slot, kSlots>> m_slots;
  std::vector<std::int64_t> m_key;
};

class DeviceMeshTables {
 public:
  /// Device bytes the tables of `layout` and the runs of `geometry` take (one allocation, each
  /// table and run 256-byte aligned).
  static std::uint64_t bytes_of(const MeshLayout& layout, const MeshGeometryCopies& geometry);
  /// Whether `layout` keeps a copy on `backend` now whose geometry has `geometry`'s key.
  static bool kept(const MeshLayout& layout, const MeshGeometryCopies& geometry, const DeviceBackend* backend);
  /// The tables of `layout` and the runs of `geometry` on `backend`: the kept copy when it is on
  /// that backend with the same geometry key, else a new one (allocated and copied; *copied +=
  /// the bytes copied), which the layout then keeps in place of any other. Throws what the
  /// backend throws (allocation, copy).
  static std::shared_ptr<const DeviceMeshTables> of(const MeshLayout& layout, const MeshGeometryCopies& geometry,
                                                    const std::shared_ptr<DeviceBackend>& backend,
                                                    std::uint64_t* copied);

  DeviceMeshTables(std::shared_ptr<DeviceBackend> backend, const MeshLayout& layout,
                   const MeshGeometryCopies& geometry);
  ~DeviceMeshTables();
  DeviceMeshTables(const DeviceMeshTables&) = delete;
  DeviceMeshTables& operator=(const DeviceMeshTables&) = delete;

  const DeviceBackend* backend() const { return m_backend.get(); }
  /// Bytes copied to make it.
  std::uint64_t bytes() const { return m_bytes; }
  /// Whether it serves a render on `backend` whose geometry has `key`.
  bool serves(const DeviceBackend* backend, const std::vector<std::int64_t>& key) const {
    return backend == m_backend.get() && key == m_key;
  }
  /// Device addresses of the tables (MeshFieldView's element, box, first, list)
  const MeshElementRef* element = nullptr;
  const double* box = nullptr;
  const std::uint64_t* first = nullptr;
  const std::uint32_t* list = nullptr;
  /// Device address of the geometry's run r (MeshGeometryCopies::runs order).
  const unsigned char* run(std::size_t r) const { return m_run[r]; }

 private:
  std::shared_ptr<DeviceBackend> m_backend;
  void* m_base = nullptr;
  std::uint64_t m_bytes = 0;
  std::vector<std::int64_t> m_key;
  std::vector<const unsigned char*> m_run;
};

}  // namespace cuda
}  // namespace tessera
