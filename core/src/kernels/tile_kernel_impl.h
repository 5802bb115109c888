#pragma once
/// The per-tile kernels as templates on the field's Value (tile_kernel.h says what they do).
/// Included only by the tile_kernel_<value>.cpp files, each of which instantiates them for
/// one Value (tile_kernel_instances.h), so that the Values compile in parallel.
#include "kernels/tile_kernel.h"
#include "kernels/tile_kernel_instances.h"
#include "kernels/tile_sampler.h"

#include "kernel/adaptive_sampling.h"
#include "kernel/kernel_dispatch.h"

#include <algorithm>
#include <array>

namespace tessera {
namespace {

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
  TileSampler<V> ts(s, medium, culled, &stop);
  if (s.target_error > 0.0) sample_adaptive(ts, s, tile, film, st, stop);
  else sample_uniform(ts, s, tile, film, st, stop);
  ts.flush(st);
}

/// The adaptive-sampling preview (adaptive_sampling.h) of one block row: per block, the
/// pilot samples' luminance sums of its middle pixel.
template <class V>
void preview_row(const KernelScene& s, int by, PilotSums* row, StopCheck& stop) {
  constexpr int B = kAdaptiveBlock;
  const int pilot = adaptive_pilot(s.spp);
  const GridMedium<V> medium = make_medium<V>(s);
  TileSampler<V> ts(s, medium, false, &stop);
  for (int bx = 0; bx * B < s.width; ++bx) {
    int x = 0, y = 0;
    preview_pixel(bx, by, s.width, s.height, &x, &y);
    PilotSums& p = row[bx];
    const bool go_on = for_samples(0, pilot, stop, [&](int i) {
      SampleResult r;
      if (ts.draw(x, y, kPreviewIndexBase + static_cast<std::uint64_t>(i), r, false)) p.add(luminance(r.L));
    });
    if (!go_on) return;
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
