/// The TBB tile scheduler: render_tiles() cuts the chosen tiles into work items, runs the
/// frame's tile kernel (tile_kernel.h, chosen once) on them in a task arena and sums the
/// counters; adaptive_preview_scale() runs the preview kernel over block rows the same way.
#include <tessera/render.h>

#include "kernel/adaptive_sampling.h"
#include "kernel/stop_check.h"
#include "kernels/tile_kernel.h"
#include "scene/prepared_scene_impl.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <chrono>
#include <numeric>
#include <stdexcept>

namespace tessera {

DeadlineExceeded::DeadlineExceeded(std::size_t tiles_done, std::size_t tiles_total)
    : std::runtime_error("render deadline passed with " + std::to_string(tiles_done) + "/" +
                         std::to_string(tiles_total) + " tiles done"),
      m_done(tiles_done),
      m_total(tiles_total) {}

namespace {

/// Worker threads for a render: options.threads (0 = the current arena's concurrency), never
/// more than TBB will run at once (global_control max_allowed_parallelism, the hardware
/// threads unless the caller lowered it). Asking for more would only create idle arena slots.
int render_threads(const RenderOptions& o) {
  const int cap = static_cast<int>(std::max<std::size_t>(
      1, tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
  const int want = o.threads > 0 ? o.threads : tbb::this_task_arena::max_concurrency();
  return std::clamp(want, 1, cap);
}

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

/// A work item's bracket for a paged field's cache (enter_tile / leave_tile, brick_cache.h):
/// lets the cache be emptied only while no worker is inside a tile. Nothing for a replicated
/// field (null cache).
class TileBracket {
 public:
  explicit TileBracket(BrickCache* cache) : m_cache(cache) {
    if (m_cache) m_cache->enter_tile();
  }
  ~TileBracket() {
    if (m_cache) m_cache->leave_tile();
  }
  TileBracket(const TileBracket&) = delete;
  TileBracket& operator=(const TileBracket&) = delete;

 private:
  BrickCache* m_cache;
};

}  // namespace

double adaptive_preview_scale(const KernelScene& s, const RenderOptions& options) {
  if (!(s.target_error > 0.0)) return 0.0;
  const int threads = render_threads(options);
  const PreviewKernel preview_row = preview_kernel(s);
  const int rows = (s.height + kAdaptiveBlock - 1) / kAdaptiveBlock;
  const int cols = (s.width + kAdaptiveBlock - 1) / kAdaptiveBlock;
  std::vector<double> sigma(rows, 0.0), lum(rows, 0.0);
  std::vector<std::uint64_t> count(rows, 0);
  StopCheck stop(options.deadline);
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(0, rows, [&](int by) {
      if (stop.stop()) return;
      TileBracket bracket(s.paged.cache);
      preview_row(s, by, &sigma[by], &lum[by], &count[by], stop);
    });
  });
  if (stop.stopped()) throw DeadlineExceeded(0, s.tile_count);
  // Row sums added in row order: the same for any thread count.
  double sigma_sum = 0.0, lum_sum = 0.0;
  std::uint64_t n = 0;
  for (int r = 0; r < rows; ++r) sigma_sum += sigma[r], lum_sum += lum[r], n += count[r];
  if (n == 0 || !(lum_sum > 0.0)) return 0.0;  // a black image: every pixel takes the pilot
  const double S_mean = sigma_sum / (static_cast<double>(rows) * cols);
  const double M = lum_sum / static_cast<double>(n);
  const double t = s.target_error;
  return S_mean / (t * t * M * M);
}

void render_tiles(const PreparedScene& scene, std::span<const int> tile_indices, Film& film,
                  RenderStats& stats, const std::function<void(int)>& progress) {
  const PreparedSceneImpl& s = prepared_scene_impl(scene);
  if (film.width() != s.desc.image.width || film.height() != s.desc.image.height)
    throw std::invalid_argument("film is " + std::to_string(film.width()) + "x" +
                                std::to_string(film.height()) + ", scene image is " +
                                std::to_string(s.desc.image.width) + "x" +
                                std::to_string(s.desc.image.height));
  const int ntiles = static_cast<int>(s.tiles.size());
  for (int i : tile_indices)
    if (i < 0 || i >= ntiles) throw std::out_of_range("tile index " + std::to_string(i) + " out of range");

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
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, work.size(), 1),
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

void render(const PreparedScene& scene, Film& film, RenderStats& stats,
            const std::function<void(int)>& progress) {
  std::vector<int> all(scene.tiles().size());
  std::iota(all.begin(), all.end(), 0);
  render_tiles(scene, all, film, stats, progress);
}

}  // namespace tessera
