#pragma once
/// Data-distributed rendering, the core side: a field that no rank holds whole, read through
/// bricks fetched on first touch into a bounded cache (a demand-paged field).
///
/// The global field of dims[0] x dims[1] x dims[2] vertices is cut into bricks of B^3
/// vertices (B = 2^shift): brick (bx, by, bz) covers vertices [bx B, min((bx+1) B, dims)) along
/// each axis. The cut depends only on the global dims and B, never on how ranks split the
/// field. A resident brick lives in a slot of B^3 elements of the field's dtype, i fastest:
/// vertex (i, j, k) of the brick's box is at element ((k - z0) B + (j - y0)) B + (i - x0),
/// whatever the brick's clipped size (the rest of a slot at the far faces is unused).
///
/// Who does what:
/// - The kernels (any number of worker threads) read vertices with PagedFieldView::load: the
///   rank's own block straight from the caller's array, every brick wholly inside another own
///   block (a rank may hold several: BrickCache::set_in_place) straight from that block's array,
///   other vertices from their brick's slot.
///   A brick that is not resident is asked for with BrickCache::acquire, which blocks the
///   worker until the brick is there. No virtual call, lock or allocation on a hit.
/// - One service thread (in situ: the thread that talks MPI) takes the wanted bricks, fills
///   their slots (from other ranks, or in tests from a full array) and publishes them.
/// - When all slots are taken, the older half of the resident bricks (in publication order) is
///   evicted at once, but only at a quiescent moment:
///   every worker is either between tiles (enter_tile blocks while a flush is pending) or
///   blocked in acquire. Kernels copy vertex values out at once and keep no slot pointer past
///   a load, so no worker can read a slot that is being reused.
///
/// Images do not depend on any of this: a vertex read from a slot has the same bits as the
/// same vertex read in place, so residency, eviction and fetch order change nothing.
///
/// On a GPU (device_brick_table.h, core/src/cuda/device_bricks.h) the kernels read every
/// vertex through a device copy of the bricks instead (PagedFieldView::device); the host fills
/// those copies through this cache like a worker, between launches.
#include <tessera/device_brick_table.h>
#include <tessera/field_view.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace tessera {

/// The global brick cut of a field (see the file comment). Plain values.
struct BrickGrid {
  std::int64_t dims[3] = {0, 0, 0};  ///< global vertices
  DType dtype = DType::Float32;
  int shift = 5;                       ///< B = 2^shift vertices per brick edge
  std::int64_t bricks[3] = {0, 0, 0};  ///< ceil(dims / B)

  /// Throws std::invalid_argument when dims < 1 or shift outside [1, 10].
  static BrickGrid make(const std::int64_t dims[3], DType dtype, int shift);
  std::int64_t edge() const { return std::int64_t{1} << shift; }
  std::int64_t brick_count() const { return bricks[0] * bricks[1] * bricks[2]; }
  std::int64_t index(std::int64_t bx, std::int64_t by, std::int64_t bz) const {
    return (bz * bricks[1] + by) * bricks[0] + bx;
  }
  /// The vertex box [lo, hi) of brick b.
  void box(std::int64_t b, std::int64_t lo[3], std::int64_t hi[3]) const;
  /// Bytes of one slot: B^3 elements.
  std::size_t slot_bytes() const { return (std::size_t{1} << (3 * shift)) * dtype_size(dtype); }
};

/// An own block other than PagedField::local, as given to BrickCache::set_in_place: its
/// elements (validated, the cache's dtype) and the global vertex of its element (0, 0, 0).
struct InPlaceBlock {
  FieldView view;
  std::int64_t offset[3] = {0, 0, 0};
};

/// How a kernel reads a vertex of an own block in place: global vertex (i, j, k) of the
/// block is the element at byte address origin + i s0 + j s1 + k s2 (the block's data minus
/// its offset times its strides, so no per-lookup offset). Plain values.
struct InPlaceAddress {
  std::intptr_t origin = 0;
  std::int64_t byte_strides[3] = {0, 0, 0};
};

/// The rank's other own blocks as the kernels find them (BrickCache::set_in_place): cells of
/// 2^shift vertices per edge (aligned to multiples of 2^shift, the last one along an axis
/// clipped at the grid) over the blocks' bounding box; each cell's entry is the index into
/// `at` of the block that holds the whole cell, or -1 (the cell straddles blocks or ranks:
/// read through the cache). Plain values, pointing into the cache.
struct InPlaceTable {
  const std::int32_t* cell = nullptr;  ///< cells[0] x cells[1] x cells[2], x fastest; null: none
  const InPlaceAddress* at = nullptr;
  std::int64_t lo[3] = {0, 0, 0};  ///< global vertex of cell (0, 0, 0)
  std::uint64_t cells[3] = {0, 0, 0};
  int shift = 0;
};

/// Counters of one render's paging (for stats and benchmarks).
struct BrickCacheStats {
  std::uint64_t fetched = 0;        ///< bricks filled and published
  std::uint64_t misses = 0;         ///< acquire() calls that had to wait
  std::uint64_t flushes = 0;        ///< times the older half of the cache was evicted to make room
  std::uint64_t peak_resident = 0;  ///< most bricks resident at once
};

class BrickCache {
 public:
  /// A cache of `capacity` slots (>= 1) over `grid`. Allocates the directory (one pointer, one
  /// state byte and one waiter count per brick of the grid), the capacity x slot_bytes() pool
  /// and one slot of zeros (for fail()) at once; allocated_bytes() says how much. Throws std::invalid_argument for capacity < 1.
  BrickCache(const BrickGrid& grid, std::size_t capacity);
  ~BrickCache();
  BrickCache(const BrickCache&) = delete;
  BrickCache& operator=(const BrickCache&) = delete;

  const BrickGrid& grid() const { return m_grid; }
  std::size_t capacity() const { return m_capacity; }
  /// Directory + state + in-place table + slot pool, in bytes (without set_in_place's
  /// addresses: in_place_bytes()).
  std::uint64_t allocated_bytes() const;
  /// Bytes the cache would allocate for `grid` and `capacity` (for memory estimates), the
  /// in-place table included; add in_place_bytes() per own block.
  static std::uint64_t bytes_for(const BrickGrid& grid, std::size_t capacity);
  /// Bytes set_in_place keeps per own block given.
  static constexpr std::uint64_t in_place_bytes() { return sizeof(InPlaceAddress); }
  /// Entries of the in-place table (4 bytes each): max(bricks, 2^18), so at most 1 MiB beyond
  /// one entry per brick.
  static std::uint64_t in_place_entries(const BrickGrid& grid);

  // ---- setup: between renders, no worker or service active ----

  /// The rank's own blocks other than PagedField::local (disjoint from it and from each other,
  /// inside the grid, of its dtype): from now on PagedFieldView::load reads every vertex of a
  /// table cell that lies wholly inside one of them in place, never through a slot. The cells
  /// are the finest (edge 2^t, 1 <= t <= the brick shift) whose table over the blocks' bounding
  /// box fits in_place_entries(); cells that straddle blocks or ranks still come through the
  /// slots. Replaces the previous call's blocks (an empty span: none); reset() keeps them.
  /// Cost O(table cells + cells each block touches). Throws std::invalid_argument naming the
  /// block for a block of another dtype, outside the grid, invalid, or covering a cell another
  /// block covers wholly.
  void set_in_place(std::span<const InPlaceBlock> blocks);
  /// The table the kernels use (cell null when no blocks are set).
  InPlaceTable in_place() const { return m_table; }
  /// Blocks of the last set_in_place call.
  std::size_t in_place_count() const { return m_in_place.size(); }
  /// Vertices the last set_in_place call made readable in place (those of its cells).
  std::uint64_t in_place_vertices() const { return m_in_place_vertices; }

  // ---- worker side: any thread, inside a render ----

  /// The slot of brick b if resident, else null. Lock-free.
  const unsigned char* find(std::int64_t b) const noexcept {
    return m_dir[static_cast<std::size_t>(b)].load(std::memory_order_acquire);
  }
  /// The slot of brick b, waiting (blocked, counted as quiescent) until the service thread
  /// has published it. After fail() it returns a slot of zeros at once (the render is then
  /// discarded by its caller). Never throws, never allocates.
  const unsigned char* acquire(std::int64_t b) noexcept;
  /// Bracket every tile (or band) a worker renders. enter_tile blocks while a flush is
  /// pending (returns at once after fail()).
  void enter_tile() noexcept;
  void leave_tile() noexcept;

  // ---- service side: one thread ----

  /// Waits up to `wait` for a worker to want a brick (or for a flush to become possible),
  /// then appends every brick wanted and not yet taken to `out`, each once, oldest first.
  void take_wanted(std::vector<std::int64_t>& out, std::chrono::microseconds wait);
  /// A free slot for wanted brick b (not yet visible to workers), or null when every slot is
  /// taken: then call try_flush() until it returns true, and reserve again.
  unsigned char* reserve(std::int64_t b);
  /// b's reserved slot is filled: makes it visible and wakes the workers waiting for it.
  void publish(std::int64_t b);
  /// Evicts the older half of the resident bricks (at least one; by publication order) if no
  /// slot is reserved-but-unpublished and every worker is quiescent; otherwise marks a flush
  /// pending (so enter_tile blocks) and returns false. Wanted bricks stay wanted.
  bool try_flush();
  /// Ends the render in failure: wakes every waiting worker (acquire returns zeros from now
  /// on) and records `why` (the first reason is kept).
  void fail(const std::string& why);
  bool failed() const { return m_failed.load(std::memory_order_acquire); }
  std::string failure() const;
  /// Empties the cache, clears fail() and the counters, for the next render.
  void reset();

  BrickCacheStats stats() const;

 private:
  struct State;
  BrickGrid m_grid;
  std::size_t m_capacity = 0;
  std::unique_ptr<std::atomic<const unsigned char*>[]> m_dir;
  std::unique_ptr<std::int32_t[]> m_in_place_cells;  ///< in_place_entries(grid) (set_in_place)
  std::vector<InPlaceAddress> m_in_place;
  InPlaceTable m_table;
  std::uint64_t m_in_place_vertices = 0;
  std::atomic<bool> m_failed{false};
  std::unique_ptr<State> m_state;  ///< mutex, condition variables, slot pool, queues, counters
};

/// What the kernels read in distributed mode: the rank's own blocks in place, other vertices
/// through the cache. Trivially copyable; a part of the KernelScene.
struct PagedFieldView {
  DType dtype = DType::Float32;
  std::int64_t dims[3] = {0, 0, 0};  ///< global vertices
  FieldView local;                   ///< the rank's own block (data null when it has none)
  std::int64_t lo[3] = {0, 0, 0};    ///< global vertex of local's (0, 0, 0)
  std::int64_t hi[3] = {0, 0, 0};    ///< lo + local.dims
  int shift = 5;
  std::int64_t bricks[3] = {0, 0, 0};
  BrickCache* cache = nullptr;
  /// The rank's other own blocks (BrickCache::set_in_place); cell null when it has none.
  InPlaceTable in_place;
  /// On a GPU: `local` is a device copy (or the caller's device array), every other vertex
  /// comes through the device's bricks (in_place empty, cache never called); slot null on the
  /// CPU.
  DeviceBrickTable device;

  /// Vertex (i, j, k) of the global field (inside dims) as double, exactly as
  /// TypedFieldView::load of the same vertex in a whole-field view gives it. Inline (the
  /// kernels' hot path): a vertex of `local` is one strided load; a vertex of a table cell
  /// wholly inside another own block one table load and one strided load (no search); another
  /// one a directory load (BrickCache::find) and a load from its slot; only a miss calls out.
  TESSERA_HOST_DEVICE double load(std::int64_t i, std::int64_t j, std::int64_t k) const;
};

static_assert(std::is_trivially_copyable_v<PagedFieldView>);

namespace detail {
/// Element at p of dtype t, as double (exact for every dtype).
TESSERA_HOST_DEVICE inline double load_as_double(DType t, const unsigned char* p) {
  switch (t) {
    case DType::UInt8: return static_cast<double>(*p);
    case DType::Int16: {
      std::int16_t v;
      __builtin_memcpy(&v, p, sizeof v);
      return static_cast<double>(v);
    }
    case DType::UInt16: {
      std::uint16_t v;
      __builtin_memcpy(&v, p, sizeof v);
      return static_cast<double>(v);
    }
    case DType::Float32: {
      float v;
      __builtin_memcpy(&v, p, sizeof v);
      return static_cast<double>(v);
    }
    case DType::Float64:
    default: {
      double v;
      __builtin_memcpy(&v, p, sizeof v);
      return v;
    }
  }
}
/// Element e of a dense array of dtype t at base, as double.
TESSERA_HOST_DEVICE inline double load_element(DType t, const unsigned char* base, std::int64_t e) {
  switch (t) {
    case DType::UInt8: return load_as_double(t, base + e);
    case DType::Int16:
    case DType::UInt16: return load_as_double(t, base + 2 * e);
    case DType::Float32: return load_as_double(t, base + 4 * e);
    case DType::Float64:
    default: return load_as_double(t, base + 8 * e);
  }
}
/// `v` stored at p in dtype t (load_as_double's inverse: exact for a value read from that
/// dtype; otherwise converted as static_cast converts).
inline void store_from_double(DType t, unsigned char* p, double v) {
  switch (t) {
    case DType::UInt8: *p = static_cast<std::uint8_t>(v); break;
    case DType::Int16: {
      const auto x = static_cast<std::int16_t>(v);
      __builtin_memcpy(p, &x, sizeof x);
      break;
    }
    case DType::UInt16: {
      const auto x = static_cast<std::uint16_t>(v);
      __builtin_memcpy(p, &x, sizeof x);
      break;
    }
    case DType::Float32: {
      const auto x = static_cast<float>(v);
      __builtin_memcpy(p, &x, sizeof x);
      break;
    }
    case DType::Float64:
    default: __builtin_memcpy(p, &v, sizeof v);
  }
}
}  // namespace detail

TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE inline double PagedFieldView::load(std::int64_t i, std::int64_t j,
                                                                               std::int64_t k) const {
  // The own block, in place
  // (one unsigned compare per axis: a vertex below lo wraps to a huge offset)
  const std::int64_t li = i - lo[0], lj = j - lo[1], lk = k - lo[2];
  if (static_cast<std::uint64_t>(li) < static_cast<std::uint64_t>(hi[0] - lo[0]) &&
      static_cast<std::uint64_t>(lj) < static_cast<std::uint64_t>(hi[1] - lo[1]) &&
      static_cast<std::uint64_t>(lk) < static_cast<std::uint64_t>(hi[2] - lo[2])) {
    const auto* p = static_cast<const unsigned char*>(local.data) + li * local.byte_strides[0] +
                    lj * local.byte_strides[1] + lk * local.byte_strides[2];
    return detail::load_as_double(dtype, p);
  }
  // A table cell wholly inside another own block, in place (a vertex outside the table's box
  // wraps to a huge cell index, as above)
  if (in_place.cell) {
    const std::uint64_t cx = static_cast<std::uint64_t>(i - in_place.lo[0]) >> in_place.shift;
    const std::uint64_t cy = static_cast<std::uint64_t>(j - in_place.lo[1]) >> in_place.shift;
    const std::uint64_t cz = static_cast<std::uint64_t>(k - in_place.lo[2]) >> in_place.shift;
    if (cx < in_place.cells[0] && cy < in_place.cells[1] && cz < in_place.cells[2]) {
      const std::int32_t d = in_place.cell[(cz * in_place.cells[1] + cy) * in_place.cells[0] + cx];
      if (d >= 0) {
        const InPlaceAddress& at = in_place.at[d];
        const std::intptr_t p = at.origin + static_cast<std::intptr_t>(i * at.byte_strides[0] + j * at.byte_strides[1] +
                                                                       k * at.byte_strides[2]);
        return detail::load_as_double(dtype, reinterpret_cast<const unsigned char*>(p));
      }
    }
  }
  // Another rank's (or a cell straddling blocks): its brick's slot, fetched on a miss
  const std::int64_t b = ((k >> shift) * bricks[1] + (j >> shift)) * bricks[0] + (i >> shift);
  const unsigned char* slot;
  if (device.slot) {
    // On a GPU: the device's copy, or 0 and the brick noted (the launch is run again)
    slot = device.slot[b];
    if (!slot) [[unlikely]] {
      note_brick_miss(device, b);
      return 0.0;
    }
    mark_brick_used(device, b);
  } else {
#if defined(__CUDA_ARCH__)
    return 0.0;  // never: a device's view always has its brick table
#else
    slot = cache->find(b);
    if (!slot) [[unlikely]]
      slot = cache->acquire(b);
#endif
  }
  const std::int64_t m = (std::int64_t{1} << shift) - 1;
  const std::int64_t e = ((((k & m) << shift) + (j & m)) << shift) + (i & m);
  return detail::load_element(dtype, slot, e);
}

/// A field rendered in distributed mode, as handed to prepare(): the global geometry, the
/// rank's own block and the cache that serves the rest.
struct PagedField {
  DType dtype = DType::Float32;
  std::int64_t dims[3] = {0, 0, 0};    ///< global vertices
  FieldView local;                     ///< own block, validated; may be empty (data null)
  std::int64_t offset[3] = {0, 0, 0};  ///< global vertex of local's (0, 0, 0)
  /// Non-null, grid dims and dtype as above; its in-place blocks (set_in_place), if any, are
  /// read in place too
  BrickCache* cache = nullptr;
  /// The own block's values in GPU memory too, when the caller has them there (the adapter:
  /// the simulation's device array whose host copy `local` is): element (0, 0, 0) of the same
  /// dims, dtype and byte strides as `local`. A GPU render reads the own block there; without
  /// it, it copies `local` to the device once per prepared scene. Never read on the CPU.
  const void* local_device = nullptr;
  /// The own block is device memory only (the adapter's distributed render of a simulation's
  /// device array on the GPU): `local` describes it and its data is `local_device`. The host
  /// then reads none of it: a CPU view (prepare's preview, the GPU's brick refills) takes its
  /// vertices through `cache` (whose filler copies them from the device, cuda_copy_box_to_host),
  /// while a GPU render reads it in place.
  bool local_device_only = false;
};

}  // namespace tessera
