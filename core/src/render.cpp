#include <tessera/render.h>

#include "adaptive_sampling.h"
#include "path_tracer.h"
#include "stop_check.h"
#include "prepared_scene_impl.h"

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

using Clock = std::chrono::steady_clock;

/// Adds one finite sample to a pixel's sums.
inline void add_sample(PixelSums& px, const SampleResult& r) {
  px.r += r.L.x;
  px.g += r.L.y;
  px.b += r.L.z;
  px.a += r.alpha;
  const double lum = luminance(r.L);
  px.lum += lum;
  px.lum2 += lum * lum;
  ++px.n;
}

/// Adds the kept sample's auxiliary features (the denoiser's albedo and normal) to the
/// pixel's AuxSums, beside add_sample: the same samples in the same order, so the sums are
/// as deterministic as the colour's.
inline void add_aux(AuxSums& aux, const SampleResult& r) {
  for (int c = 0; c < 3; ++c) {
    aux.albedo[c] += r.albedo[c];
    aux.normal[c] += r.normal[c];
  }
}

/// One tile's sampling: draws samples of pixels with the tile's tracer and counters.
template <class T, Shading S, bool kEmission>
class TileSampler {
 public:
  TileSampler(const PreparedSceneImpl& s, const GridMedium<T>& medium, bool culled, StopCheck& stop)
      : m_s(s), m_tracer(s, medium, &stop), m_culled(culled) {}

  /// Sample `index` of pixel (x, y); false if its radiance is not finite. `own`: the pixel is
  /// in this tile, so the tile's culling applies (another tile's pixel is always traced: a
  /// culled tile's verdict says nothing about its neighbours, and a traced miss gives the
  /// same value as a culled fill).
  bool draw(int x, int y, std::uint64_t index, SampleResult& r, bool own = true) {
    const std::uint64_t pixel = static_cast<std::uint64_t>(y) * m_s.desc.image.width + x;
    Rng rng(m_s.desc.options.seed, m_s.desc.options.frame, pixel, index);
    const double jx = rng.uniform(), jy = rng.uniform();
    const double lx = rng.uniform(), ly = rng.uniform();
    const Ray ray = m_s.camera.generate(x + jx, y + jy, lx, ly);
    // A culled tile's rays meet nothing: exactly the background a traced miss returns.
    r = m_culled && own ? SampleResult{m_s.env.visible() ? m_s.env.eval(ray.d) : Color(0.0), 0.0}
                        : m_tracer.li(ray, rng, m_k);
    return is_finite(r.L);
  }

  /// Draw sample `index` of the pixel into its sums, and into `aux` when given (a non-finite
  /// one is counted and dropped). Returns the sample when it was kept, for the caller's own
  /// bookkeeping.
  const SampleResult* accumulate(int x, int y, PixelSums& px, AuxSums* aux, std::uint64_t index,
                                 RenderStats& st) {
    ++st.samples;
    ++px.drawn;
    if (!draw(x, y, index, m_last)) {
      ++st.discarded_samples;
      return nullptr;
    }
    add_sample(px, m_last);
    if (aux) add_aux(*aux, m_last);
    return &m_last;
  }

  /// Adds the tracer's counts (field lookups, collisions, stalled paths) to `st`.
  void flush(RenderStats& st) const { st.add_counters(m_k); }

 private:
  const PreparedSceneImpl& m_s;
  const PathTracer<T, S, kEmission> m_tracer;
  KernelCounters m_k;
  SampleResult m_last;
  bool m_culled;
};

/// Calls fn(si) for si in [begin, end) in order, polling the deadline before each run of
/// kPollSamples samples (a pixel's adaptive samples can number spp). False if stopped.
constexpr std::int64_t kPollSamples = 1024;
template <class Fn>
bool for_samples(int begin, int end, StopCheck& stop, Fn&& fn) {
  for (std::int64_t c = begin; c < end; c += kPollSamples) {
    if (stop.stop()) return false;
    const int e = static_cast<int>(std::min<std::int64_t>(end, c + kPollSamples));
    for (int si = static_cast<int>(c); si < e; ++si) fn(si);
  }
  return true;
}

/// Uniform sampling: all spp estimates of the tile, sample-major.
template <class T, Shading S, bool E>
void sample_uniform(TileSampler<T, S, E>& ts, const PreparedSceneImpl& s, const Tile& tile,
                    Film& film, RenderStats& st, StopCheck& stop) {
  for (int si = 0; si < s.desc.image.spp && !stop.stop(); ++si)
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        PixelSums& px = film.at(x, y);
        ts.accumulate(x, y, px, film.aux_at(x, y), px.drawn, st);  // continues the pixel's sample indices
      }
}

/// Adaptive sampling (adaptive_sampling.h), block by block. Every pixel's samples have indices
/// 0..n-1 in every call, whatever the film holds, so that a tile can redraw the pilot samples
/// of block pixels outside it (identical values, used for the decision only, not counted in
/// `samples`) however the tiles are split across calls or ranks: free when tiles are
/// multiples of the block, pilot-sized otherwise.
template <class T, Shading S, bool E>
void sample_adaptive(TileSampler<T, S, E>& ts, const PreparedSceneImpl& s, const Tile& tile,
                     Film& film, RenderStats& st, StopCheck& stop) {
  constexpr int B = kAdaptiveBlock;
  const int width = s.desc.image.width, height = s.desc.image.height, spp = s.desc.image.spp;
  const int pilot = adaptive_pilot(spp);
  std::array<PilotSums, B * B> sums;
  const auto inside = [&](int x, int y) { return x >= tile.x0 && x < tile.x1 && y >= tile.y0 && y < tile.y1; };
  for (int by = tile.y0 / B * B; by < tile.y1; by += B) {
    for (int bx = tile.x0 / B * B; bx < tile.x1; bx += B) {
      if (stop.stop()) return;
      const int bw = std::min(B, width - bx), bh = std::min(B, height - by);
      // Pilot: every pixel of the block, in raster order.
      for (int j = 0; j < bh; ++j) {
        for (int i = 0; i < bw; ++i) {
          const int x = bx + i, y = by + j;
          PilotSums& p = sums[static_cast<std::size_t>(j * B + i)];
          p = PilotSums{};
          const bool mine = inside(x, y);
          const bool go_on = for_samples(0, pilot, stop, [&](int si) {
            SampleResult r;
            const SampleResult* kept = nullptr;
            if (mine) {
              kept = ts.accumulate(x, y, film.at(x, y), film.aux_at(x, y), static_cast<std::uint64_t>(si), st);
            } else if (ts.draw(x, y, static_cast<std::uint64_t>(si), r, false)) {
              kept = &r;
            }
            if (kept) p.add(luminance(kept->L));
          });
          if (!go_on) return;
        }
      }
      // The rest of each own pixel's samples, counted from the other pixels' pilots.
      for (int j = 0; j < bh; ++j) {
        for (int i = 0; i < bw; ++i) {
          const int x = bx + i, y = by + j;
          if (!inside(x, y)) continue;
          PilotSums others;
          for (int q = 0; q < bh * B; ++q)
            if (q != j * B + i && q % B < bw) others.add(sums[static_cast<std::size_t>(q)]);
          const int n = adaptive_count(others, pilot, spp, s.adaptive_scale);
          PixelSums& px = film.at(x, y);
          AuxSums* aux = film.aux_at(x, y);
          if (!for_samples(pilot, n, stop, [&](int si) { ts.accumulate(x, y, px, aux, static_cast<std::uint64_t>(si), st); }))
            return;
        }
      }
    }
  }
}

/// Render one tile (or a band of one, see plan_work): all its samples before the next one.
/// `culled`: the tile's culling verdict.
template <class T, Shading S, bool E>
void render_tile(const PreparedSceneImpl& s, const GridMedium<T>& medium,
                 const Tile& tile, bool culled, Film& film, RenderStats& st, StopCheck& stop) {
  TileSampler<T, S, E> ts(s, medium, culled, stop);
  if (s.desc.image.target_error > 0.0) sample_adaptive(ts, s, tile, film, st, stop);
  else sample_uniform(ts, s, tile, film, st, stop);
  ts.flush(st);
}

using TileFn = void (*)(const PreparedSceneImpl&, const void* medium, const Tile&, bool culled, Film&,
                        RenderStats&, StopCheck&);

template <class T, Shading S, bool E>
void tile_entry(const PreparedSceneImpl& s, const void* medium, const Tile& t, bool culled, Film& f,
                RenderStats& st, StopCheck& stop) {
  render_tile<T, S, E>(s, *static_cast<const GridMedium<T>*>(medium), t, culled, f, st, stop);
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

template <class T>
TileFn pick_kernel(const PreparedSceneImpl& s) {
  const bool e = s.has_emission;
  switch (s.desc.integrator.shading) {
    case Shading::Phase: return e ? tile_entry<T, Shading::Phase, true> : tile_entry<T, Shading::Phase, false>;
    case Shading::Brdf: return e ? tile_entry<T, Shading::Brdf, true> : tile_entry<T, Shading::Brdf, false>;
    case Shading::Hybrid: default:
      return e ? tile_entry<T, Shading::Hybrid, true> : tile_entry<T, Shading::Hybrid, false>;
  }
}

template <class T>
GridMedium<T> make_medium(const PreparedSceneImpl& s, TypedFieldView<T> view) {
  GridMedium<T> m;
  m.field = view;
  for (int a = 0; a < 3; ++a) {
    m.n[a] = s.field.dims[a];
    m.hi_index[a] = static_cast<double>(s.field.dims[a] - 1);
    m.nc[a] = s.grid.cells()[a];
  }
  m.tf = &s.desc.tf;
  m.sigma_max = s.sigma_max;
  m.majorant = s.grid.majorants();
  m.cell_edge = s.grid.edge();
  return m;
}

/// The adaptive-sampling preview (adaptive_sampling.h) of one block row: per block, sigma of
/// the luminance of `pilot` samples of its middle pixel, and those samples' luminance sum.
template <class T, Shading S, bool E>
void preview_row(const PreparedSceneImpl& s, const GridMedium<T>& medium, int by, double* sigma_sum,
                 double* lum_sum, std::uint64_t* count, StopCheck& stop) {
  constexpr int B = kAdaptiveBlock;
  const int width = s.desc.image.width, height = s.desc.image.height;
  const int pilot = adaptive_pilot(s.desc.image.spp);
  TileSampler<T, S, E> ts(s, medium, false, stop);
  const int y = std::min(by * B + B / 2, height - 1);
  for (int bx = 0; bx * B < width; ++bx) {
    const int x = std::min(bx * B + B / 2, width - 1);
    PilotSums p;
    const bool go_on = for_samples(0, pilot, stop, [&](int i) {
      SampleResult r;
      if (ts.draw(x, y, kPreviewIndexBase + static_cast<std::uint64_t>(i), r, false)) p.add(luminance(r.L));
    });
    if (!go_on) return;
    *sigma_sum += p.sigma();
    *lum_sum += p.lum;
    *count += p.n;
  }
}

template <class T, Shading S, bool E>
double preview_scale(const PreparedSceneImpl& s, const GridMedium<T>& medium, int threads) {
  const int rows = (s.desc.image.height + kAdaptiveBlock - 1) / kAdaptiveBlock;
  const int cols = (s.desc.image.width + kAdaptiveBlock - 1) / kAdaptiveBlock;
  std::vector<double> sigma(rows, 0.0), lum(rows, 0.0);
  std::vector<std::uint64_t> count(rows, 0);
  StopCheck stop(s.desc.options.deadline);
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(0, rows, [&](int by) {
      if (!stop.stop()) preview_row<T, S, E>(s, medium, by, &sigma[by], &lum[by], &count[by], stop);
    });
  });
  if (stop.stopped()) throw DeadlineExceeded(0, s.tiles.size());
  // Row sums added in row order: the same for any thread count.
  double sigma_sum = 0.0, lum_sum = 0.0;
  std::uint64_t n = 0;
  for (int r = 0; r < rows; ++r) sigma_sum += sigma[r], lum_sum += lum[r], n += count[r];
  if (n == 0 || !(lum_sum > 0.0)) return 0.0;  // a black image: every pixel takes the pilot
  const double S_mean = sigma_sum / (static_cast<double>(rows) * cols);
  const double M = lum_sum / static_cast<double>(n);
  const double t = s.desc.image.target_error;
  return S_mean / (t * t * M * M);
}

}  // namespace

void render_tiles(const PreparedScene& scene, std::span<const int> tile_indices, Film& film,
                  RenderStats& stats, const std::function<void(int)>& progress) {
  const PreparedSceneImpl& s = scene.impl();
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
  dispatch_dtype(s.field, [&](auto view) {
    using T = typename decltype(view)::value_type;
    const GridMedium<T> medium = make_medium(s, view);
    const TileFn fn = pick_kernel<T>(s);
    tbb::task_arena arena(threads);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, work.size(), 1),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                            if (stop.stop()) return;  // the deadline: skip the rest
                            const WorkItem& w = work[i];
                            const std::size_t tile = static_cast<std::size_t>(tile_indices[w.tile]);
                            fn(s, &medium, w.rect, s.tile_culled[tile] != 0, film, per_item[i], stop);
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
  });
  // Integer counters: the sum is the same whatever the schedule.
  for (const RenderStats& t : per_item) stats.add_counters(t);
  for (const int i : tile_indices) stats.tiles_skipped += s.tile_culled[static_cast<std::size_t>(i)] != 0;
  stats.tiles_total += tile_indices.size();
  stats.nan_voxels_seen = s.grid.nan_vertices();  // a property of the field, counted at prepare
  stats.threads = threads;
  stats.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (stop.stopped()) throw DeadlineExceeded(static_cast<std::size_t>(done.load()), tile_indices.size());
}

double adaptive_preview_scale(const PreparedSceneImpl& s) {
  if (!(s.desc.image.target_error > 0.0)) return 0.0;
  const int threads = render_threads(s.desc.options);
  return dispatch_dtype(s.field, [&](auto view) {
    using T = typename decltype(view)::value_type;
    const GridMedium<T> medium = make_medium(s, view);
    const bool e = s.has_emission;
    switch (s.desc.integrator.shading) {
      case Shading::Phase:
        return e ? preview_scale<T, Shading::Phase, true>(s, medium, threads)
                 : preview_scale<T, Shading::Phase, false>(s, medium, threads);
      case Shading::Brdf:
        return e ? preview_scale<T, Shading::Brdf, true>(s, medium, threads)
                 : preview_scale<T, Shading::Brdf, false>(s, medium, threads);
      case Shading::Hybrid: default:
        return e ? preview_scale<T, Shading::Hybrid, true>(s, medium, threads)
                 : preview_scale<T, Shading::Hybrid, false>(s, medium, threads);
    }
  });
}

void render(const PreparedScene& scene, Film& film, RenderStats& stats,
            const std::function<void(int)>& progress) {
  std::vector<int> all(scene.tiles().size());
  std::iota(all.begin(), all.end(), 0);
  render_tiles(scene, all, film, stats, progress);
}

}  // namespace tessera
