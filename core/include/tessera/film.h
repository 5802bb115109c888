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
  std::uint64_t n = 0;      ///< samples accumulated
  std::uint64_t drawn = 0;  ///< samples drawn (accumulated + discarded): next sample index
};

/// Sums of the denoiser's auxiliary features over a pixel's kept samples (the same samples,
/// in the same order, as its PixelSums): albedo and shading normal of each sample's first
/// real collision, zero for a sample that met nothing.
struct AuxSums {
  double albedo[3] = {0, 0, 0};
  double normal[3] = {0, 0, 0};
};

class Film {
 public:
  Film() = default;
  /// `aux`: also keep AuxSums per pixel (for denoising; render_tiles fills them iff present).
  Film(int width, int height, bool aux = false);
  int width() const { return m_width; }
  int height() const { return m_height; }

  PixelSums& at(int x, int y) { return m_px[static_cast<std::size_t>(y) * m_width + x]; }
  const PixelSums& at(int x, int y) const { return m_px[static_cast<std::size_t>(y) * m_width + x]; }
  std::vector<PixelSums>& pixels() { return m_px; }
  const std::vector<PixelSums>& pixels() const { return m_px; }
  bool has_aux() const { return !m_aux.empty(); }
  /// The pixel's auxiliary sums, or nullptr when the film has none.
  AuxSums* aux_at(int x, int y) { return m_aux.empty() ? nullptr : &m_aux[static_cast<std::size_t>(y) * m_width + x]; }
  std::vector<AuxSums>& aux() { return m_aux; }
  const std::vector<AuxSums>& aux() const { return m_aux; }

  /// Mean per pixel, variance of the mean (luminance) and sample count; pixels with no
  /// sample are black with alpha 0. With auxiliary sums, also the image's albedo and normal
  /// (sum / count, like the colour).
  Image resolve(bool with_variance = true, bool with_samples = true) const;
  void clear();

 private:
  int m_width = 0, m_height = 0;
  std::vector<PixelSums> m_px;
  std::vector<AuxSums> m_aux;  ///< empty unless made with aux
};

}  // namespace tessera
