#pragma once
/// DeviceBrickTable: a distributed (paged) field's bricks as the GPU backend's kernels read
/// them (the host side: core/src/cuda/device_bricks.h; docs/gpu.md, "Distributed fields").
/// Per brick of the cut the device address of its slot, null while the brick is not on the
/// device. A lookup in a missing brick notes the brick and reads 0: the launch is discarded
/// and run again once the host has copied the noted bricks over, so no image ever holds
/// such a value.
///
/// Notes come in two kinds. The first miss of a sample's path is *certain*: every value the
/// path read before it was the field's, so the complete path reads that brick too. Later
/// misses of the same sample are *guesses*: the path went on through zeros, which the real
/// field may not let it reach. The host fetches every note when the pool has room, and only
/// the certain ones when it does not, so a pool too small for the guesses still renders.
#include <tessera/host_device.h>

#include <atomic>
#include <cstdint>

namespace tessera {

struct DeviceBrickTable {
  const unsigned char* const* slot = nullptr;  ///< per brick; null: not a device render
  /// Per brick: bit 0 once it is in `certain`, bit 1 once it is in `guess` (this launch)
  unsigned int* wanted = nullptr;
  std::int64_t* certain = nullptr;  ///< certain notes, in order (list_capacity entries)
  std::int64_t* guess = nullptr;    ///< guesses, in order (list_capacity entries)
  /// [0]: certain notes made, [1]: guesses made (either may pass list_capacity). [0] is
  /// nonzero once the launch missed any brick (a sample's first miss is certain).
  unsigned long long* count = nullptr;
  unsigned long long list_capacity = 0;
  /// Per thread of the launch (its index in the launch): nonzero once its current sample
  /// missed a brick. Device renders only; the host emulation keeps it per host thread.
  unsigned char* path_missed = nullptr;
  unsigned long long path_capacity = 0;  ///< entries of path_missed
  /// Per brick: nonzero once a lookup of the launch read it (the host evicts the bricks read
  /// longest ago first)
  unsigned char* used = nullptr;
};

namespace detail {

/// The host emulation's per-thread "this sample has missed" (DeviceBrickTable::path_missed).
inline thread_local bool host_path_missed = false;

/// Adds b to `list` (counted by *count) unless `bit` of wanted[b] was set. Any thread.
TESSERA_HOST_DEVICE inline void note_brick(unsigned int* wanted, unsigned int bit, std::int64_t* list,
                                           unsigned long long* count, unsigned long long capacity, std::int64_t b) {
#if defined(__CUDA_ARCH__)
  if ((*static_cast<volatile const unsigned int*>(&wanted[b]) & bit) != 0u || (atomicOr(&wanted[b], bit) & bit) != 0u)
    return;
  const unsigned long long at = atomicAdd(count, 1ull);
#else
  std::atomic_ref<unsigned int> w(wanted[b]);
  if ((w.load(std::memory_order_relaxed) & bit) != 0u || (w.fetch_or(bit, std::memory_order_relaxed) & bit) != 0u)
    return;
  const unsigned long long at = std::atomic_ref<unsigned long long>(*count).fetch_add(1, std::memory_order_relaxed);
#endif
  if (at < capacity) list[at] = b;
}

}  // namespace detail

/// Brick b missed on the device: noted as certain (the sample's first miss) or as a guess.
TESSERA_HOST_DEVICE inline void note_brick_miss(const DeviceBrickTable& t, std::int64_t b) {
#if defined(__CUDA_ARCH__)
  const unsigned long long thread = static_cast<unsigned long long>(blockIdx.x) * blockDim.x + threadIdx.x;
  bool first = true;
  if (thread < t.path_capacity) {
    first = t.path_missed[thread] == 0;
    t.path_missed[thread] = 1;
  }
#else
  const bool first = !detail::host_path_missed;
  detail::host_path_missed = true;
#endif
  if (first) detail::note_brick(t.wanted, 1u, t.certain, &t.count[0], t.list_capacity, b);
  else detail::note_brick(t.wanted, 2u, t.guess, &t.count[1], t.list_capacity, b);
}

/// Brick b (resident) was read on the device. Any thread.
TESSERA_HOST_DEVICE inline void mark_brick_used(const DeviceBrickTable& t, std::int64_t b) {
#if defined(__CUDA_ARCH__)
  if (t.used[b] == 0) t.used[b] = 1;  // every writer stores the same byte
#else
  std::atomic_ref<unsigned char> u(t.used[b]);
  if (u.load(std::memory_order_relaxed) == 0) u.store(1, std::memory_order_relaxed);
#endif
}

/// A thread of a launch (its index `thread`) begins a sample: nothing missed yet.
TESSERA_HOST_DEVICE inline void begin_brick_sample(unsigned char* path_missed, [[maybe_unused]] std::int64_t thread) {
#if defined(__CUDA_ARCH__)
  if (path_missed) path_missed[thread] = 0;
#else
  (void)path_missed;
  detail::host_path_missed = false;
#endif
}

}  // namespace tessera
