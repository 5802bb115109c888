#pragma once
/// Adaptive sampling (image.target_error > 0): how many samples each pixel gets.
///
/// Contract (docs/physics.md section 11):
///  - The image is cut into fixed kAdaptiveBlock^2 pixel blocks, aligned to pixel (0, 0) and
///    independent of the render tiles. Every pixel first takes `pilot` samples.
///  - A pixel's total count is decided from the pilot samples of the OTHER pixels of its block
///    (leave one out) and from a preview, never from its own samples: its samples are then
///    independent of how many of them are taken, so its mean stays an unbiased estimate
///    (stopping on a pixel's own variance is optional stopping, and biased). All of the pixel's
///    samples, pilot included, are kept.
///  - n = ceil(sigma * scale), clamped to [pilot, spp]: sigma is the standard deviation per
///    sample of luminance pooled over the others' pilots, and scale = S / (target^2 M^2) comes
///    from the preview (prepare time: one pixel per block, `pilot` samples each, on random
///    streams the image never uses), with S its mean per-pixel sigma and M its mean
///    luminance. Samples in proportion to sigma minimise the image's MSE for the samples
///    spent; the scale makes the expected relative RMSE of the image, sqrt(mean sigma^2 / n) /
///    M, equal to the target when no clamp binds. Fewer than two other pilot samples: n = spp.
///  - Pure functions of pilot and preview samples, which are pure functions of (seed, frame,
///    pixel, index): identical for any tile size, order, thread count or MPI split.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

namespace tessera {

inline constexpr int kAdaptiveBlock = 8;

/// Blocks along an image axis of `pixels` pixels (the last one may be partial).
constexpr int adaptive_blocks(int pixels) { return (pixels + kAdaptiveBlock - 1) / kAdaptiveBlock; }

/// Pilot samples per pixel for a render of `spp` samples.
inline int adaptive_pilot(int spp) { return std::min(spp, std::max(8, spp / 16)); }

/// Luminance sums of pilot samples (finite ones only): one pixel's, or several pixels' pooled.
struct PilotSums {
  double lum = 0.0, lum2 = 0.0;
  std::uint64_t n = 0;

  void add(double l) {
    lum += l;
    lum2 += l * l;
    ++n;
  }
  void add(const PilotSums& o) {
    lum += o.lum;
    lum2 += o.lum2;
    n += o.n;
  }
  /// Standard deviation per sample (unbiased variance); 0 with fewer than two samples.
  double sigma() const {
    if (n < 2) return 0.0;
    const double c = static_cast<double>(n), mean = lum / c;
    return std::sqrt(std::max(0.0, (lum2 - lum * mean) / (c - 1.0)));
  }
};

/// Sample index of the preview's i-th sample of a pixel: far above any count a film reaches,
/// so preview streams are never the image's.
inline constexpr std::uint64_t kPreviewIndexBase = std::uint64_t{1} << 62;

/// The preview's pixel of block (bx, by): the block's middle, inside a width x height image.
inline void preview_pixel(int bx, int by, int width, int height, int* x, int* y) {
  *x = std::min(bx * kAdaptiveBlock + kAdaptiveBlock / 2, width - 1);
  *y = std::min(by * kAdaptiveBlock + kAdaptiveBlock / 2, height - 1);
}

/// The preview's scale S / (target^2 M^2) from its blocks' pilot sums (row-major, rows of
/// `cols` blocks), added block by block within a row and then row by row, so that the host's
/// preview (scene/adaptive_preview.cpp) and the device's (cuda/device_render.cpp) reach the
/// same bits from the same sums. 0 for a black preview (every pixel then takes the pilot).
inline double preview_scale(std::span<const PilotSums> blocks, int cols, double target_error) {
  const std::size_t c = static_cast<std::size_t>(cols);
  const std::size_t rows = c > 0 ? blocks.size() / c : 0;
  double sigma_sum = 0.0, lum_sum = 0.0;
  std::uint64_t n = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    double sigma = 0.0, lum = 0.0;
    std::uint64_t count = 0;
    for (std::size_t b = r * c; b < (r + 1) * c; ++b) {
      sigma += blocks[b].sigma();
      lum += blocks[b].lum;
      count += blocks[b].n;
    }
    sigma_sum += sigma, lum_sum += lum, n += count;
  }
  if (n == 0 || !(lum_sum > 0.0)) return 0.0;
  const double S_mean = sigma_sum / (static_cast<double>(rows) * cols);
  const double M = lum_sum / static_cast<double>(n);
  return S_mean / (target_error * target_error * M * M);
}

/// Samples for a pixel given the summed pilots of the other pixels of its block and the
/// preview's scale (KernelScene::adaptive_scale).
inline int adaptive_count(const PilotSums& others, int pilot, int spp, double scale) {
  if (others.n < 2) return spp;
  const double need = others.sigma() * scale;
  if (!(need < static_cast<double>(spp))) return spp;  // also NaN
  return std::clamp(static_cast<int>(std::ceil(need)), pilot, spp);
}

}  // namespace tessera
