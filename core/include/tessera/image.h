#pragma once
/// A plain float image: what a Film resolves to and what the writers and readers exchange.
#include <cstdint>
#include <vector>

namespace tessera {

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgba;      ///< width*height*4, row 0 = top, linear radiance; A = alpha
  std::vector<float> variance;  ///< optional: width*height, variance of the pixel mean (luminance)
  std::vector<float> samples;   ///< optional: width*height, sample count per pixel
  /// Optional (denoising): width*height*3 each. albedo: mean albedo of the first real
  /// collision, in [0, 1]; normal: mean world-space shading normal there, in [-1, 1];
  /// 0 where a sample met nothing. denoised: the denoised RGB (denoiser.h); when present,
  /// write_png shows it instead of rgba's RGB and write_exr adds it as denoised.R/G/B.
  std::vector<float> albedo;
  std::vector<float> normal;
  std::vector<float> denoised;
  float* px(int x, int y) { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
  const float* px(int x, int y) const { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
};

}  // namespace tessera
