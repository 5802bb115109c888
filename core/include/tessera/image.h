#pragma once
/// A plain float image: what a Film resolves to and what the writers and readers exchange.
#include <cstdint>
#include <vector>

namespace tessera {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgba;       ///< width*height*4, row 0 = top, linear radiance; A = alpha
  std::vector<float> variance;   ///< optional: width*height, variance of the pixel mean (luminance)
  std::vector<float> samples;    ///< optional: width*height, sample count per pixel
  float* px(int x, int y) { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
  const float* px(int x, int y) const { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
};

}  // namespace tessera
