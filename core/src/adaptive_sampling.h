#pragma once
/// Adaptive sampling (image.target_error > 0): how many samples each pixel gets.
///
/// Contract (docs/physics.md section 11):
///  - The image is cut into fixed kBlock x kBlock pixel blocks, aligned to pixel (0, 0) and
///    independent of the render tiles. Every pixel first takes `pilot` samples.
///  - A pixel's total count is decided from the pilot samples of the OTHER pixels of its block
///    (leave one out), never from its own: its samples are independent of how many of them are
///    taken, so its mean stays an unbiased estimate (stopping on a pixel's own variance is
///    optional stopping and biased). All of the pixel's samples, pilot included, are kept.
///  - From the pooled luminance mean and variance per sample of those others, the coefficient
///    of variation cv = sqrt(var) / max(mean, kMeanFloor) gives n = ceil(cv / target^2),
///    clamped to [pilot, spp]. Samples in proportion to cv is the allocation that minimises
///    the image's mean relative squared error for the samples spent (minimise
///    sum cv^2 / n subject to sum n fixed); target_error is then the relative standard error
///    reached by a pixel with cv = 1 (in general target * sqrt(cv)). Equalising every pixel's
///    relative error instead (n ~ cv^2) costs as much as uniform sampling for the same mean
///    error and was measured slower than it (docs/BENCHMARKS.md). Fewer than two other pilot
///    samples: no information, n = spp.
///  - Pure functions of pilot samples, which are pure functions of (seed, frame, pixel, index):
///    identical for any tile size, order, thread count or MPI split.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace tessera {

inline constexpr int kAdaptiveBlock = 8;
inline constexpr double kAdaptiveMeanFloor = 0.01;  ///< luminance below which error is absolute

/// Pilot samples per pixel for a render of `spp` samples.
inline int adaptive_pilot(int spp) { return std::min(spp, std::max(8, spp / 16)); }

/// Luminance sums of one pixel's pilot samples (finite ones only).
struct PilotSums {
  double lum = 0.0, lum2 = 0.0;
  std::uint64_t n = 0;
};

/// Samples for a pixel given the summed pilots of the other pixels of its block.
inline int adaptive_count(const PilotSums& others, int pilot, int spp, double target) {
  if (others.n < 2) return spp;
  const double n = static_cast<double>(others.n);
  const double mean = others.lum / n;
  const double var = std::max(0.0, (others.lum2 - others.lum * mean) / (n - 1.0));
  const double cv = std::sqrt(var) / std::max(std::fabs(mean), kAdaptiveMeanFloor);
  const double need = cv / (target * target);
  if (!(need < static_cast<double>(spp))) return spp;  // also NaN
  return std::clamp(static_cast<int>(std::ceil(need)), pilot, spp);
}

}  // namespace tessera
