#pragma once
/// DeviceBricks: a distributed (paged) field's bricks on the GPU (docs/gpu.md, "Distributed
/// fields"). A kernel cannot wait for a brick that lives on another rank, so the device
/// renders by replay:
/// - the device holds the rank's own block (PagedFieldView::local: the caller's device array
///   or a copy), a bounded pool of brick slots and a directory (per brick of the cut the
///   device address of its slot, or null), DeviceBrickTable;
/// - a lookup in a brick that is not resident notes it (once per launch; certain or a guess,
///   device_brick_table.h) and reads 0, and every lane of that launch stops after its
///   current sample; the host then restores the launch's sums and counters, copies the noted
///   bricks over (filled on the host through the host's PagedFieldView: the rank's own blocks
///   in place, other ranks' bricks through the host BrickCache and its service thread) and
///   runs the launch again;
/// - only a launch that ran without a miss is kept, so every value it read is the field's,
///   and the image is the bits of the same scene rendered on the device from a whole field.
/// The host half of render_on_device calls this class between launches only (no kernel then
/// reads the directory), so evicting is always safe. Not thread-safe: one render at a time
/// (DeviceScene serialises them).
#include <tessera/brick_cache.h>

#include "cuda/device_backend.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace tessera::cuda {

/// What one round of DeviceBricks::fetch did.
struct BrickRound {
  std::uint64_t fetched = 0;  ///< bricks copied to the device
  /// The certain bricks asked for could not all be resident at once with those the launch
  /// read or was sure of since `since` (making room evicted one of them, or no room was
  /// left): the launch should be split.
  bool overflow = false;
};

class DeviceBricks {
 public:
  /// The cut of `host`'s field into bricks.
  static BrickGrid grid_of(const PagedFieldView& host);
  /// Device bytes for `capacity` slots over the cut of `host` and launches of up to
  /// `threads` threads (directory, flags, the two lists of notes, counts, a byte per thread,
  /// slots), each part aligned to 256 bytes.
  static std::uint64_t bytes_for(const PagedFieldView& host, std::size_t capacity, std::uint64_t threads);
  /// The slots a device budget of `bytes` holds beside the rest (0 when not even one).
  static std::size_t capacity_for(const PagedFieldView& host, std::uint64_t bytes, std::uint64_t threads);

  /// Over `bytes_for(host, capacity, threads)` bytes of device memory at `base` (the
  /// backend's); `host` (the prepared scene's view) fills the slots and must outlive this.
  DeviceBricks(DeviceBackend& backend, const PagedFieldView& host, std::size_t capacity, std::uint64_t threads,
               unsigned char* base);

  /// Every brick absent, no brick noted; returns the bytes written to the device.
  std::uint64_t reset();
  /// The view the kernels read: `host` with its own block at device address `local` (same
  /// dims and strides; null: none) and every other vertex through the device's bricks.
  PagedFieldView device_view(const void* local) const;
  /// The device address of the launch's count of certain notes (SliceArgs::missed: nonzero
  /// once it missed any brick) and of its per-thread flags (SliceArgs::path_missed).
  const unsigned long long* missed() const { return m_count; }
  unsigned char* path_missed() const { return m_path; }
  /// Threads a launch may have at most.
  std::uint64_t max_threads() const { return m_threads; }
  std::size_t capacity() const { return m_capacity; }
  /// False before reset() and after a fetch that threw (the directory may then be stale):
  /// reset() before the next launch.
  bool valid() const { return m_valid; }

  /// What the launch just run noted (device_brick_table.h): its counts read back, then its
  /// lists, into `certain` and `guesses` (replaced); the flags and counts zeroed for the
  /// next launch. False when it missed nothing (then nothing else was read or written).
  /// *more (when given): it noted more certain bricks than the list holds.
  bool take_noted(std::vector<std::int64_t>& certain, std::vector<std::int64_t>& guesses, bool* more = nullptr);
  /// Makes the `certain` bricks resident and as many `guesses` as fit without evicting a
  /// brick of the current launch (read or fetched since `since`, stamp() when it first ran),
  /// each filled on the host and copied over. A full pool evicts first the bricks the launch
  /// has not touched, read longest ago first, then its unread guesses (for a certain brick
  /// only); BrickRound::overflow when a certain brick would evict one it read or was sure of,
  /// i.e. its bricks do not fit together. Throws
  /// std::runtime_error naming the host cache's failure (a rank's service failed) or a CUDA
  /// error.
  BrickRound fetch(std::span<const std::int64_t> certain, std::span<const std::int64_t> guesses, std::uint64_t since);
  /// After every launch (kept or not): the bricks it read are marked as read now (eviction
  /// takes those read longest ago first), the marks cleared; the launch count goes up.
  void after_launch();
  /// The launch count: pass its value when a launch first ran as fetch's `since`.
  std::uint64_t stamp() const { return m_stamp; }

  std::uint64_t bytes_to_device() const { return m_to_device; }
  std::uint64_t bytes_to_host() const { return m_to_host; }
  std::uint64_t fetched() const { return m_fetched; }

 private:
  void fill(std::int64_t b, unsigned char* out) const;
  /// b resident (fetched now unless it was), a victim evicted when the pool is full (fetch's
  /// order); `since` as for fetch. A guess: false, nothing done, when room would take a brick
  /// of the current launch. A certain brick: r.overflow when room takes one the launch read or
  /// was sure of, or when every resident brick came in this round (then b stays out).
  bool bring(std::int64_t b, bool guess, std::uint64_t since, BrickRound& r);

  DeviceBackend& m_b;
  const PagedFieldView& m_host;
  BrickGrid m_grid;
  std::size_t m_capacity;
  // Device addresses
  const unsigned char** m_dir = nullptr;
  unsigned int* m_wanted = nullptr;
  unsigned char* m_used = nullptr;  ///< per brick: read by the launch
  std::int64_t* m_certain = nullptr;
  std::int64_t* m_guess = nullptr;
  unsigned long long* m_count = nullptr;  ///< [0] certain notes, [1] guesses
  unsigned char* m_path = nullptr;        ///< a byte per thread
  std::uint64_t m_threads = 0;
  unsigned char* m_pool = nullptr;
  // Host bookkeeping
  std::vector<const unsigned char*> m_dir_host;  ///< per brick: its slot's device address or null
  std::vector<std::uint64_t> m_serial_of;        ///< per brick: the serial it was fetched with
  std::vector<std::uint64_t> m_last;             ///< per brick: the launch that last read or fetched it
  std::vector<bool> m_guessed;                   ///< per brick: fetched as a guess, not read since
  std::vector<unsigned char> m_used_host;        ///< the use marks read back
  std::vector<std::int64_t> m_victims;           ///< a fetch's eviction order (made at its first eviction)
  std::size_t m_next_victim = 0;
  std::vector<unsigned char*> m_free;   ///< free slots
  std::vector<unsigned char> m_buffer;  ///< one slot, filled on the host
  std::uint64_t m_serial = 0, m_stamp = 1;
  bool m_valid = false;
  bool m_changed = false;  ///< the host directory differs from the device's
  std::uint64_t m_to_device = 0, m_to_host = 0, m_fetched = 0;
};

}  // namespace tessera::cuda
