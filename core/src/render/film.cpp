#include <tessera/film.h>

#include <algorithm>
#include <stdexcept>

namespace tessera {

Film::Film(int width, int height, bool aux) : m_width(width), m_height(height) {
  if (width < 1 || height < 1) throw std::invalid_argument("film must be at least 1x1");
  m_px.assign(static_cast<std::size_t>(width) * height, PixelSums{});
  if (aux) m_aux.assign(m_px.size(), AuxSums{});
}

void Film::clear() {
  m_px.assign(m_px.size(), PixelSums{});
  m_aux.assign(m_aux.size(), AuxSums{});
}

Image Film::resolve(bool with_variance, bool with_samples) const {
  Image img;
  img.width = m_width;
  img.height = m_height;
  const std::size_t n = m_px.size();
  img.rgba.assign(n * 4, 0.0f);
  if (with_variance) img.variance.assign(n, 0.0f);
  if (with_samples) img.samples.assign(n, 0.0f);
  if (has_aux()) {
    img.albedo.assign(n * 3, 0.0f);
    img.normal.assign(n * 3, 0.0f);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const PixelSums& p = m_px[i];
    if (with_samples) img.samples[i] = static_cast<float>(p.n);
    if (p.n == 0) continue;
    const double inv = 1.0 / static_cast<double>(p.n);
    img.rgba[4 * i + 0] = static_cast<float>(p.r * inv);
    img.rgba[4 * i + 1] = static_cast<float>(p.g * inv);
    img.rgba[4 * i + 2] = static_cast<float>(p.b * inv);
    img.rgba[4 * i + 3] = static_cast<float>(p.a * inv);
    if (has_aux()) {
      for (int c = 0; c < 3; ++c) {
        img.albedo[3 * i + c] = static_cast<float>(m_aux[i].albedo[c] * inv);
        img.normal[3 * i + c] = static_cast<float>(m_aux[i].normal[c] * inv);
      }
    }
    if (with_variance && p.n > 1) {
      // Unbiased sample variance of luminance, divided by n: variance of the pixel mean.
      const double mean = p.lum * inv;
      const double var = std::max(0.0, (p.lum2 - p.lum * mean) / static_cast<double>(p.n - 1));
      img.variance[i] = static_cast<float>(var * inv);
    }
  }
  return img;
}

}  // namespace tessera
