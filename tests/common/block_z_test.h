#pragma once
// The block z-test of two independent films (the mesh and GPU suites): per block of
// edge x edge pixels, the mean of the pixel means and its standard error from each pixel's
// sample variance, and the largest |z| between two films' blocks.
#include <tessera/film.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace tessera_test {

/// Mean luminance and its standard error over one block of pixels.
struct BlockStat {
  double mean = 0.0, se = 0.0;
};

/// Per block of `edge` x `edge` pixels: mean of the pixel means and its standard error from
/// each pixel's sample variance.
inline std::vector<BlockStat> block_stats(const tessera::Film& film, int edge) {
  std::vector<BlockStat> out;
  for (int by = 0; by + edge <= film.height(); by += edge)
    for (int bx = 0; bx + edge <= film.width(); bx += edge) {
      double m = 0.0, var = 0.0;
      for (int y = by; y < by + edge; ++y)
        for (int x = bx; x < bx + edge; ++x) {
          const tessera::PixelSums& p = film.pixels()[static_cast<std::size_t>(y * film.width() + x)];
          const double n = static_cast<double>(p.n), pm = p.lum / n;
          m += pm;
          if (p.n > 1) var += std::fmax(0.0, (p.lum2 - p.lum * pm) / (n - 1.0)) / n;
        }
      const double np = static_cast<double>(edge * edge);
      out.push_back({m / np, std::sqrt(var) / np});
    }
  return out;
}

/// The largest |z| over the blocks of two independent films (standard errors combined; a
/// floor of 1e-9 absolute keeps two empty blocks at z 0).
inline double max_block_z(const tessera::Film& a, const tessera::Film& b, int edge) {
  const std::vector<BlockStat> sa = block_stats(a, edge), sb = block_stats(b, edge);
  double z = 0.0;
  for (std::size_t i = 0; i < sa.size(); ++i) {
    const double se = std::sqrt(sa[i].se * sa[i].se + sb[i].se * sb[i].se);
    z = std::max(z, std::fabs(sa[i].mean - sb[i].mean) / std::fmax(se, 1e-9));
  }
  return z;
}

}  // namespace tessera_test
