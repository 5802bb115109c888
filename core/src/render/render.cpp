/// The TBB tile scheduler: render_tiles() cuts the chosen tiles into work items, runs the
/// frame's tile kernel (tile_kernel.h, chosen once) on them in a task arena and sums the
/// counters. prepare's adaptive preview (scene/adaptive_preview.cpp) runs the same way.
#include <tessera/render.h>

#include <tessera/cuda_render.h>

#include "kernel/adaptive_sampling.h"
#include "kernel/stop_check.h"
#include "kernels/tile_kernel.h"
#include "kernels/workers.h"
#include "render/tiles_call.h"
#include "scene/prepared_scene_impl.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace tessera {

DeadlineExceeded::DeadlineExceeded(std::size_t tiles_done, std::size_t tiles_total)
    : std::runtime_error("render deadline passed with " + std::to_string(tiles_done) + "/" +
                         std::to_string(tiles_total) + " tiles done"),
      m_done(tiles_done),
      m_total(tiles_total) {}

namespace {

/// A unit of parallel work: one tile, or a band of rows of one.
struct WorkItem {
  Tile rect;
  std::size_t tile;  ///< position in the caller's tile list
};

/// With one thread, or at least kTasksPerThread tiles per thread, each tile is one task. With
/// fewer (large tiles, a small image, a short tile list under MPI) and several threads, tiles
/// are cut into bands of kBandRows rows, aligned to multiples of kBandRows image rows (so adaptive 8x8 blocks stay whole), so
/// that threads are not left idle behind a few heavy tiles. Pixels keep their samples in index
/// order either way: the image is the same bit for bit.
constexpr std::size_t kTasksPerThread = 4;
constexpr int kBandRows = 8;
static_assert(kBandRows % kAdaptiveBlock == 0);

std::vector<WorkItem> plan_work(const PreparedSceneImpl& s, std::span<const int> tiles, int threads) {
  std::vector<WorkItem> work;
  const bool split = threads > 1 && tiles.size() < kTasksPerThread * static_cast<std::size_t>(threads);
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const Tile& t = s.tiles[static_cast<std::size_t>(tiles[i])];
    if (!split) {
      work.push_back({t, i});
      continue;
    }
    for (int y0 = t.y0; y0 < t.y1;) {
      const int y1 = std::min(t.y1, (y0 / kBandRows + 1) * kBandRows);
      Tile band = t;
      band.y0 = y0;
      band.y1 = y1;
      work.push_back({band, i});
      y0 = y1;
    }
  }
  return work;
}

/// The GPU's render_tiles: the options' device, stream and memory limit, the bytes copied
/// counted in stats, progress reported once at the end (the device has no per-tile callback).
void render_on_gpu(const PreparedScene& scene, std::span<const int> tile_indices, Film& film, RenderStats& stats,
                   const std::function<void(int)>& progress) {
  const RenderOptions& o = scene.desc().options;
  CudaLaunch launch;
  launch.device = o.cuda_device;
  launch.stream = o.cuda_stream;
  launch.memory_limit_bytes = o.device_memory_limit;
  CudaTransfer transfer;
  const auto count_bytes = [&] {
    stats.bytes_to_device += transfer.bytes_to_device;
    stats.bytes_to_host += transfer.bytes_to_host;
  };
  try {
    render_tiles_cuda(scene, tile_indices, film, stats, launch, &transfer);
  } catch (const DeadlineExceeded&) {
    count_bytes();  // the film holds the work done, as on the CPU
    throw;
  }
  count_bytes();
  if (progress) progress(static_cast<int>(tile_indices.size()));
}

}  // namespace

void render_tiles(const PreparedScene& scene, std::span<const int> tile_indices, Film& film, RenderStats& stats,
                  const std::function<void(int)>& progress) {
  const PreparedSceneImpl& s = prepared_scene_impl(scene);
  check_tiles_call(s, film, tile_indices);
  if (s.desc.options.device == Device::Cuda) {
    render_on_gpu(scene, tile_indices, film, stats, progress);
    return;
  }
  if (s.mesh.on_device())  // prepare refuses it; the host never reads device arrays
    throw std::logic_error("render_tiles: a mesh in device memory renders on the GPU only");

  const int threads = render_threads(s.desc.options);
  const std::vector<WorkItem> work = plan_work(s, tile_indices, threads);
  std::vector<RenderStats> per_item(work.size());
  // Progress counts whole tiles: a tile is done when its last band is.
  std::vector<std::atomic<int>> bands_left(tile_indices.size());
  for (const WorkItem& w : work) bands_left[w.tile].fetch_add(1, std::memory_order_relaxed);
  std::atomic<int> done{0};
  std::atomic<bool> reporting{false};
  StopCheck stop(s.desc.options.deadline);
  const auto t_start = std::chrono::steady_clock::now();
  const KernelScene& ks = s.kernel;
  const TileKernel render_tile = tile_kernel(ks);  // the frame's variant, chosen once
  {
    tbb::task_arena arena(threads);
    arena.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, work.size(), 1),
          [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
              if (stop.stop()) return;  // the deadline: skip the rest
              const WorkItem& w = work[i];
              const std::size_t tile = static_cast<std::size_t>(tile_indices[w.tile]);
              {
                TileBracket bracket(ks.paged.cache);
                render_tile(ks, w.rect, s.tile_culled[tile] != 0, film, per_item[i], stop);
              }
              if (stop.stopped()) return;  // possibly cut short: not done
              if (bands_left[w.tile].fetch_sub(1) != 1) continue;
              const int d = ++done;
              if (progress && !reporting.exchange(true)) {
                progress(d);
                reporting = false;
              }
            }
          },
          // One task per item: the auto partitioner grouped neighbouring tiles
          // into one task, so a few heavy tiles (a small volume in a big image)
          // could end on one thread.
          tbb::simple_partitioner());
    });
  }
  // Integer counters: the sum is the same whatever the schedule.
  for (const RenderStats& t : per_item) stats.add_counters(t);
  for (const int i : tile_indices) stats.tiles_skipped += s.tile_culled[static_cast<std::size_t>(i)] != 0;
  stats.tiles_total += tile_indices.size();
  stats.nan_voxels_seen = s.grid.nan_vertices();  // a property of the field, counted at prepare
  stats.threads = threads;
  stats.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (stop.stopped()) throw DeadlineExceeded(static_cast<std::size_t>(done.load()), tile_indices.size());
}

void render(const PreparedScene& scene, Film& film, RenderStats& stats, const std::function<void(int)>& progress) {
  std::vector<int> all(scene.tiles().size());
  std::iota(all.begin(), all.end(), 0);
  render_tiles(scene, all, film, stats, progress);
}

}  // namespace tessera
