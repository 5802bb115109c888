#pragma once
/// The sizes of the wavefront loop's scratch (kernels/wave_kernel.h), for the host half that
/// allocates it before a slice (device_render.cpp) and counts it in the memory limit: a
/// function of the slice's thread count only. Plain data; host and device.
#include "kernel/kernel_scene.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace tessera::cuda {

/// Bytes a slot may take, whatever the Value (wave_kernel.h asserts it): the scratch of a slice
/// is sized with it before its Value's kernel is chosen.
inline constexpr std::size_t kWaveSlotBytes = 1152;
/// Path slots of one slice at most (144 MiB of slots): about half the threads an H100 or
/// H200 keeps resident (132 SMs of 2048), enough for the walks' kernel to fill the card while
/// the longest lanes finish; each lane left waits for a slot. To be tuned on a GPU.
inline constexpr std::int64_t kWaveSlots = std::int64_t{1} << 17;
/// Tracking steps a walk takes per round at most: a walk not ended goes on in the next round,
/// so a warp of walks runs as long as this, not as its longest walk (bench/warp_model's
/// wavefront replay: 4 steps give 2.8x fewer warp steps than path regeneration on the head CT
/// with multiple scattering, 8 tracking steps a collision's code). To be tuned on a GPU.
inline constexpr int kWaveSteps = 4;
/// Rounds the host runs between two reads of the queues' counts (rounds after the last one
/// with work find empty queues and do nothing).
inline constexpr int kWaveRoundsPerCheck = 8;

/// The wavefront's sizes: path slots at most, tracking steps per round (a backend's choice;
/// any values give the same image).
struct WaveTuning {
  std::int64_t slots = kWaveSlots;
  int steps = kWaveSteps;
};

/// The counts of one parity's two queues: slots in a walk, slots between walks.
struct WaveCounts {
  unsigned long long walks;
  unsigned long long betweens;
};
/// The head of a slice's scratch: the next lane a slot takes, and the queues' counts by
/// parity (a round of parity p runs the queues of p and fills those of 1 - p).
struct WaveHeader {
  unsigned long long next_lane;
  unsigned long long unused;
  WaveCounts q[2];
};
inline constexpr std::size_t kWaveQueueOffset = 256;

/// Slots for a slice of `threads` lanes: min(threads, cap), at least 1 (cap: kWaveSlots on a
/// GPU; the host emulation's tests take fewer, so that slots take several lanes each).
inline std::int64_t wave_slot_count(std::int64_t threads, std::int64_t cap = kWaveSlots) {
  return std::clamp<std::int64_t>(threads, 1, std::max<std::int64_t>(cap, 1));
}
/// Bytes of one queue of `slots` slots (rounded up to 256: what follows stays aligned).
inline std::size_t wave_queue_bytes(std::int64_t slots) {
  return (static_cast<std::size_t>(slots) * sizeof(std::uint32_t) + 255) / 256 * 256;
}
/// Scratch bytes of a slice of `threads` lanes: the header, four queues (walks and betweens,
/// two parities) and the slots; a function of the thread count and cap only.
inline std::size_t wave_scratch_bytes(std::int64_t threads, std::int64_t cap = kWaveSlots) {
  const std::int64_t n = wave_slot_count(threads, cap);
  return kWaveQueueOffset + 4 * wave_queue_bytes(n) + static_cast<std::size_t>(n) * kWaveSlotBytes;
}

/// True when a scene's slices may run the wavefront: its Value (kernel_dispatch.h's
/// with_value) is not a distributed (paged) field, whose brick misses are noted per thread of
/// a launch (those keep LaneLoop::Regenerate).
inline bool wave_applies(const KernelScene& ks) {
  const bool paged =
      ks.amr.nlevels == 0 && ks.mesh.element == nullptr && !ks.magnitude.active() && ks.paged.cache != nullptr;
  return !paged;
}

}  // namespace tessera::cuda
