#pragma once
/// The per-tile kernels as templates on the field's Value (tile_kernel.h says what they do).
/// Included only by the tile_kernel_<value>.cpp files, each of which instantiates them for
/// one Value (tile_kernel_instances.h), so that the Values compile in parallel.
#include "kernels/tile_kernel.h"
#include "kernels/tile_kernel_instances.h"

#include "kernel/adaptive_sampling.h"
#include "kernel/kernel_dispatch.h"
#include "kernel/path_tracer.h"

#include <algorithm>
#include <array>

namespace tessera {
namespace {

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
template <class V>
class TileSampler {
 public:
  TileSampler(const KernelScene& s, const GridMedium<V>& medium, bool culled, StopCheck& stop)
      : m_s(s), m_tracer(s, medium, &stop), m_culled(culled) {}

  /// Sample `index` of pixel (x, y); false if its radiance is not finite. `own`: the pixel is
  /// in this tile, so the tile's culling applies (another tile's pixel is always traced: a
  /// culled tile's verdict says nothing about its neighbours, and a traced miss gives the
  /// same value as a culled fill).
  bool draw(int x, int y, std::uint64_t index, SampleResult& r, bool own = true) {
    const std::uint64_t pixel = static_cast<std::uint64_t>(y) * m_s.width + x;
    Rng rng(m_s.seed, m_s.frame, pixel, index);
    // The pixel jitter, the lens and the first collision's samples from a scrambled Sobol'
    // sequence when the scene says so (sobol_sampler.h), else from the sample's stream
    if (m_s.sampler == SamplerKind::Sobol) {
      const SobolSampler ld(m_s.seed, m_s.frame, pixel, index);
      return trace(x, y, rng, &ld, own, r);
    }
    return trace(x, y, rng, nullptr, own, r);
  }

  /// Draw sample `index` of the pixel into its sums, and into `aux` when given (a non-finite
  /// one is counted and dropped). Returns the sample when it was kept, for the caller's own
  /// bookkeeping.
  const SampleResult* accumulate(int x, int y, PixelSums& px, AuxSums* aux, std::uint64_t index, RenderStats& st) {
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
  /// The sample's camera ray and its radiance, with the sampler of draw().
  bool trace(int x, int y, Rng& rng, const SobolSampler* ld, bool own, SampleResult& r) {
    const Sample2 j = sample_2d(ld, SampleDim::Pixel, rng);
    // (a pinhole reads no lens sample: the stream still draws it, as it always has)
    const Sample2 l = ld && m_s.camera.is_pinhole() ? Sample2{0.0, 0.0} : sample_2d(ld, SampleDim::Lens, rng);
    const Ray ray = m_s.camera.generate(x + j.x, y + j.y, l.x, l.y);
    // A culled tile's rays meet nothing: exactly the background a traced miss returns.
    r = m_culled && own ? SampleResult{m_s.lights.background_visible() ? m_s.lights.background(ray.d) : Color(0.0), 0.0}
                        : m_tracer.li(ray, rng, m_k, ld);
    return is_finite(r.L);
  }

  const KernelScene& m_s;
  const PathTracer<V> m_tracer;
  KernelCounters m_k;
  SampleResult m_last;
  bool m_culled;
};

/// Calls fn(si) for si in [begin, end) in order, polling the deadline before each run of
/// kPollSamples samples (a pixel's samples can number spp): at a few microseconds a sample, the
/// poll's relaxed load and clock read cost under 0.1%, and a render stops within 64 samples of
/// one pixel of its deadline. False if stopped.
constexpr std::int64_t kPollSamples = 64;
template <class Fn>
bool for_samples(int begin, int end, StopCheck& stop, Fn&& fn) {
  for (std::int64_t c = begin; c < end; c += kPollSamples) {
    if (stop.stop()) return false;
    const int e = static_cast<int>(std::min<std::int64_t>(end, c + kPollSamples));
    for (int si = static_cast<int>(c); si < e; ++si) fn(si);
  }
  return true;
}

/// Uniform sampling: all spp estimates of the tile, pixel-major: a pixel's samples one after
/// the other, since they follow nearly the same rays through voxels and macrocells still in
/// the first-level cache (sample-major order swept the whole tile between two of them). The
/// image is the same either way: each pixel's samples are drawn and added in index order.
template <class V>
void sample_uniform(TileSampler<V>& ts, const KernelScene& s, const Tile& tile, Film& film, RenderStats& st,
                    StopCheck& stop) {
  for (int y = tile.y0; y < tile.y1; ++y)
    for (int x = tile.x0; x < tile.x1; ++x) {
      PixelSums& px = film.at(x, y);
      AuxSums* aux = film.aux_at(x, y);
      // continues the pixel's sample indices (accumulate counts px.drawn up)
      if (!for_samples(0, s.spp, stop, [&](int) { ts.accumulate(x, y, px, aux, px.drawn, st); })) return;
    }
}

/// Adaptive sampling (adaptive_sampling.h), block by block. Every pixel's samples have indices
/// 0..n-1 in every call, whatever the film holds, so that a tile can redraw the pilot samples
/// of block pixels outside it (identical values, used for the decision only, not counted in
/// `samples`) however the tiles are split across calls or ranks: free when tiles are
/// multiples of the block, pilot-sized otherwise.
template <class V>
void sample_adaptive(TileSampler<V>& ts, const KernelScene& s, const Tile& tile, Film& film, RenderStats& st,
                     StopCheck& stop) {
  constexpr int B = kAdaptiveBlock;
  const int width = s.width, height = s.height, spp = s.spp;
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
          if (!for_samples(pilot, n, stop,
                           [&](int si) { ts.accumulate(x, y, px, aux, static_cast<std::uint64_t>(si), st); }))
            return;
        }
      }
    }
  }
}

/// Render one tile (or a band of one, see plan_work in render.cpp): all its samples before
/// the next one. `culled`: the tile's culling verdict.
template <class V>
void render_tile(const KernelScene& s, const Tile& tile, bool culled, Film& film, RenderStats& st, StopCheck& stop) {
  const GridMedium<V> medium = make_medium<V>(s);
  TileSampler<V> ts(s, medium, culled, stop);
  if (s.target_error > 0.0) sample_adaptive(ts, s, tile, film, st, stop);
  else sample_uniform(ts, s, tile, film, st, stop);
  ts.flush(st);
}

/// The adaptive-sampling preview (adaptive_sampling.h) of one block row: per block, sigma of
/// the luminance of `pilot` samples of its middle pixel, and those samples' luminance sum.
template <class V>
void preview_row(const KernelScene& s, int by, double* sigma_sum, double* lum_sum, std::uint64_t* count,
                 StopCheck& stop) {
  constexpr int B = kAdaptiveBlock;
  const int width = s.width, height = s.height;
  const int pilot = adaptive_pilot(s.spp);
  const GridMedium<V> medium = make_medium<V>(s);
  TileSampler<V> ts(s, medium, false, stop);
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

}  // namespace

template <class V>
TileKernel tile_kernel_for() {
  return &render_tile<V>;
}

template <class V>
PreviewKernel preview_kernel_for() {
  return &preview_row<V>;
}

}  // namespace tessera
