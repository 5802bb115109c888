/// replay_slice (replay_slice.h).
#include "cuda/replay_slice.h"

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace tessera::cuda {

namespace {

/// Tries of one launch that cannot be split further whose bricks still do not fit the pool
/// together before replay_slice gives up.
constexpr int kMaxUnsplittableTries = 16;

}  // namespace

bool replay_slice(DeviceBackend& b, DeviceBricks& bricks, const KernelScene& dispatch, SliceArgs a,
                  const ReplayRoom& keep, const CudaLaunch& launch, StopCheck& stop, const std::string& name,
                  int& launches, int& replays) {
  struct Unit {
    std::int64_t j0, j1;
    int k0, k1;
  };
  std::vector<Unit> todo = {{a.j0, a.j1, a.k0, a.k1}};  // a stack: the next unit last
  std::vector<std::int64_t> certain, guesses;
  a.missed = bricks.missed();
  a.path_missed = bricks.path_missed();
  const auto lanes = static_cast<std::size_t>(a.lanes);
  if (static_cast<std::uint64_t>(a.j1 - a.j0) * lanes > bricks.max_threads())
    throw std::logic_error("render_tiles_cuda: a launch of " +
                           std::to_string(static_cast<std::uint64_t>(a.j1 - a.j0) * lanes) +
                           " threads over a distributed field, more than its " + std::to_string(bricks.max_threads()));
  while (!todo.empty()) {
    const Unit u = todo.back();
    todo.pop_back();
    const std::uint64_t since = bricks.stamp();
    const std::size_t first = static_cast<std::size_t>(u.j0) * lanes;
    const std::size_t n = static_cast<std::size_t>(u.j1 - u.j0) * lanes;
    int unsplittable = 0;
    // The sums and counters as they are before the unit (each try starts from them)
    b.copy_on_device(keep.px, a.lane_px + first, n * sizeof(PixelSums), "sample lanes' sums");
    if (a.lane_aux) b.copy_on_device(keep.aux, a.lane_aux + first, n * sizeof(AuxSums), "sample lanes' sums");
    b.copy_on_device(keep.counters, a.counters, kCounterCount * sizeof(unsigned long long), "counters");
    for (;;) {
      if (stop.stop()) return false;
      a.j0 = u.j0;
      a.j1 = u.j1;
      a.k0 = u.k0;
      a.k1 = u.k1;
      b.run_slice(dispatch, a, launch.block_threads, name);
      ++launches;
      bricks.after_launch();
      bool more = false;
      if (!bricks.take_noted(certain, guesses, &more)) break;  // every value it read was the field's: kept
      // Discarded: the sums and counters as they were, the bricks over, and again
      b.copy_on_device(a.lane_px + first, keep.px, n * sizeof(PixelSums), "sample lanes' sums");
      if (a.lane_aux) b.copy_on_device(a.lane_aux + first, keep.aux, n * sizeof(AuxSums), "sample lanes' sums");
      b.copy_on_device(a.counters, keep.counters, kCounterCount * sizeof(unsigned long long), "counters");
      ++replays;
      const BrickRound r = bricks.fetch(certain, guesses, since);
      if (!r.overflow && !more) continue;
      // Its bricks do not fit together: halves
      if (u.j1 - u.j0 > 1) {
        const std::int64_t mid = u.j0 + (u.j1 - u.j0) / 2;
        todo.push_back({mid, u.j1, u.k0, u.k1});
        todo.push_back({u.j0, mid, u.k0, u.k1});
        break;
      }
      if (u.k1 - u.k0 > 1) {
        const int mid = u.k0 + (u.k1 - u.k0) / 2;
        todo.push_back({u.j0, u.j1, mid, u.k1});
        todo.push_back({u.j0, u.j1, u.k0, mid});
        break;
      }
      // One sample of one pixel: its path may still fit (some bricks noted were read only
      // by the tries' paths through missing bricks), but not forever
      if (++unsplittable >= kMaxUnsplittableTries) {
        PixelJob job{};  // which pixel, for the message
        b.copy_to_host(&job, a.jobs + u.j0, sizeof job, "pixel list");
        throw std::runtime_error("render_tiles_cuda: distributed field: one sample's path (pixel (" +
                                 std::to_string(job.x) + ", " + std::to_string(job.y) + "), the call's sample " +
                                 std::to_string(u.k0) + ") needs more bricks at once than the device's pool of " +
                                 std::to_string(bricks.capacity()) +
                                 " holds; raise tessera.brick_cache or memory_limit_mb, or render on the CPU");
      }
    }
  }
  return true;
}

}  // namespace tessera::cuda
