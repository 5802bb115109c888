#pragma once
/// Film: per-pixel accumulation of radiance samples, in double precision.
///
/// Each pixel keeps the sums of its samples (RGB, alpha, luminance and luminance^2) and the
/// count; the pixel value is sum / count. Samples of one pixel are always added in sample-index
/// order by one thread, so the result does not depend on threads, tiles or their order.
#include <tessera/image.h>
#include <tessera/math.h>

#include <cstdint>
#include <vector>

namespace tessera {

struct PixelSums {
  double r = 0, g = 0, b = 0, a = 0;
  double lum = 0, lum2 = 0;
  std::uint64_t n = 0;       ///< samples accumulated
  std::uint64_t drawn = 0;   ///< samples drawn (accumulated + discarded): next sample index
};

class Film {
 public:
  Film() = default;
  Film(int width, int height);
  int width() const { return m_width; }
  int height() const { return m_height; }

  PixelSums& at(int x, int y) { return m_px[static_cast<std::size_t>(y) * m_width + x]; }
  const PixelSums& at(int x, int y) const { return m_px[static_cast<std::size_t>(y) * m_width + x]; }
  std::vector<PixelSums>& pixels() { return m_px; }
  const std::vector<PixelSums>& pixels() const { return m_px; }

  /// Mean per pixel, variance of the mean (luminance) and sample count; pixels with no
  /// sample are black with alpha 0.
  Image resolve(bool with_variance = true, bool with_samples = true) const;
  void clear();

 private:
  int m_width = 0, m_height = 0;
  std::vector<PixelSums> m_px;
};

}  // namespace tessera
