#include <tessera/render.h>

#include "path_tracer.h"
#include "prepared_scene_impl.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <numeric>
#include <stdexcept>

namespace tessera {
namespace {

/// Adaptive sampling: a pixel stops once it has min_spp samples and the relative standard
/// error of its mean luminance, sqrt(var / n) / max(mean, 0.01), is below `target`. A pure
/// function of the pixel's own sums, so the decision does not depend on tiles, threads or ranks.
inline bool pixel_converged(const PixelSums& px, int min_spp, double target) {
  if (px.n < static_cast<std::uint64_t>(min_spp) || px.n < 2) return false;
  const double n = static_cast<double>(px.n);
  const double mean = px.lum / n;
  const double var = std::max(0.0, (px.lum2 - px.lum * mean) / (n - 1.0));
  return std::sqrt(var / n) < target * std::max(mean, 0.01);
}

/// Render every sample of one tile: all spp estimates of the tile before the next tile.
template <class T, Shading S, bool kEmission>
void render_tile(const PreparedSceneImpl& s, const GridMedium<T>& medium, const Tile& tile,
                 Film& film, RenderStats& st) {
  const PathTracer<T, S, kEmission> tracer(s, medium);
  KernelCounters k;
  const bool culled = s.tile_culled[static_cast<std::size_t>(&tile - s.tiles.data())] != 0;
  if (culled) ++st.tiles_skipped;
  const int spp = s.desc.image.spp;
  const int width = s.desc.image.width;
  const double target = s.desc.image.target_error;
  const int min_spp = std::min(spp, std::max(8, spp / 16));
  for (int si = 0; si < spp; ++si) {
    for (int y = tile.y0; y < tile.y1; ++y) {
      for (int x = tile.x0; x < tile.x1; ++x) {
        PixelSums& px = film.at(x, y);
        if (target > 0.0 && pixel_converged(px, min_spp, target)) continue;
        const std::uint64_t pixel = static_cast<std::uint64_t>(y) * width + x;
        Rng rng(s.desc.options.seed, s.desc.options.frame, pixel, px.drawn);
        ++px.drawn;
        const double jx = rng.uniform(), jy = rng.uniform();
        const double lx = rng.uniform(), ly = rng.uniform();
        const Ray ray = s.camera.generate(x + jx, y + jy, lx, ly);
        // A culled tile's rays meet nothing: exactly the background a traced miss returns.
        const SampleResult r = culled ? SampleResult{s.env.visible() ? s.env.eval(ray.d) : Color(0.0), 0.0}
                                      : tracer.li(ray, rng, k);
        ++st.samples;
        if (!is_finite(r.L)) {
          ++st.discarded_samples;
          continue;
        }
        px.r += r.L.x;
        px.g += r.L.y;
        px.b += r.L.z;
        px.a += r.alpha;
        const double lum = luminance(r.L);
        px.lum += lum;
        px.lum2 += lum * lum;
        ++px.n;
      }
    }
  }
  st.free_flight_lookups += k.free_flight;
  st.transmittance_lookups += k.transmittance;
  st.gradient_lookups += k.gradient;
  st.real_collisions += k.real;
  st.null_collisions += k.null;
}

using TileFn = void (*)(const PreparedSceneImpl&, const void* medium, const Tile&, Film&, RenderStats&);

template <class T, Shading S, bool E>
void tile_entry(const PreparedSceneImpl& s, const void* medium, const Tile& t, Film& f, RenderStats& st) {
  render_tile<T, S, E>(s, *static_cast<const GridMedium<T>*>(medium), t, f, st);
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
  m.majorant = s.grid.majorants();
  m.cell_edge = s.grid.edge();
  return m;
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

  std::vector<RenderStats> per_tile(tile_indices.size());
  std::atomic<int> done{0};
  std::atomic<bool> reporting{false};
  const int threads = s.desc.options.threads > 0 ? s.desc.options.threads
                                                 : tbb::this_task_arena::max_concurrency();
  const auto t_start = std::chrono::steady_clock::now();
  dispatch_dtype(s.field, [&](auto view) {
    using T = typename decltype(view)::value_type;
    const GridMedium<T> medium = make_medium(s, view);
    const TileFn fn = pick_kernel<T>(s);
    tbb::task_arena arena(threads);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tile_indices.size(), 1),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                            fn(s, &medium, s.tiles[tile_indices[i]], film, per_tile[i]);
                            const int d = ++done;
                            if (progress && !reporting.exchange(true)) {
                              progress(d);
                              reporting = false;
                            }
                          }
                        });
    });
  });
  // Integer counters: the sum is the same whatever the schedule.
  for (const RenderStats& t : per_tile) stats.add_counters(t);
  stats.tiles_total += tile_indices.size();
  stats.nan_voxels_seen = s.grid.nan_vertices();  // a property of the field, counted at prepare
  stats.threads = threads;
  stats.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
}

void render(const PreparedScene& scene, Film& film, RenderStats& stats,
            const std::function<void(int)>& progress) {
  std::vector<int> all(scene.tiles().size());
  std::iota(all.begin(), all.end(), 0);
  render_tiles(scene, all, film, stats, progress);
}

}  // namespace tessera
