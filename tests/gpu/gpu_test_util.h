#pragma once
// What the GPU tests share: a heat-like field and scene, renders on either side, the block
// z-test (statistics in test_gpu_render.cpp's header) and a bitwise comparison of films.
#include <tessera/cuda_render.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <numeric>
#include <vector>

namespace gpu_test {

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

/// A heat-like field: a hot Gaussian spot over a cooler gradient, n^3 vertices of type T.
template <class T>
std::vector<T> heat_field(int n) {
  std::vector<T> v(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = i / (n - 1.0) - 0.55, y = j / (n - 1.0) - 0.45, z = k / (n - 1.0) - 0.5;
        const double t = 300.0 + 900.0 * std::exp(-(x * x + y * y + z * z) / 0.03) + 80.0 * (j / (n - 1.0));
        v[(static_cast<std::size_t>(k) * n + j) * n + i] = static_cast<T>(t);
      }
  return v;
}

/// The heat scene: multiple scattering, hybrid shading, a rect light and a gradient sky.
inline tessera::SceneDesc heat_scene(int n, std::uint64_t seed) {
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (n - 1));
  s.tf.lo = 300.0;
  s.tf.hi = 1300.0;
  s.tf.density_scale = 12.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.15, 0.6, 1.0}, {0.0, 0.2, 0.8, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 0.5, 1.0}, {Color(0.2, 0.3, 0.9), Color(0.9, 0.6, 0.2), Color(1.0, 0.9, 0.8)});
  s.camera.position = Vec3(1.6, 1.1, -1.9);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 35.0;
  s.background.type = tessera::BackgroundType::Gradient;
  s.background.top = Color(0.6, 0.7, 0.9);
  s.background.middle = Color(0.3);
  s.background.bottom = Color(0.05);
  tessera::RectLightDesc l;
  l.position = Vec3(0.5, 2.5, 0.5);
  l.target = Vec3(0.5, 0.5, 0.5);
  l.width = l.height = 0.8;
  l.radiance = Color(6.0);
  s.lights.push_back(l);
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 8;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.macrocell = 4;
  s.image = {48, 48, 32, 0.0};
  s.options.seed = seed;
  return s;
}

inline std::vector<int> all_tiles(const tessera::PreparedScene& ps) {
  std::vector<int> t(ps.tiles().size());
  std::iota(t.begin(), t.end(), 0);
  return t;
}

inline tessera::Film render_gpu(const tessera::PreparedScene& ps, const tessera::CudaLaunch& launch = {},
                                tessera::CudaTransfer* transfer = nullptr, tessera::RenderStats* stats = nullptr) {
  tessera::Film film(ps.desc().image.width, ps.desc().image.height);
  tessera::RenderStats st;
  tessera::render_tiles_cuda(ps, all_tiles(ps), film, st, launch, transfer);
  if (stats) *stats = st;
  return film;
}

inline tessera::Film render_cpu(const tessera::PreparedScene& ps) {
  tessera::Film film(ps.desc().image.width, ps.desc().image.height);
  tessera::RenderStats st;
  tessera::render(ps, film, st);
  return film;
}

struct BlockStat {
  double mean, se;
};

/// Per block of edge x edge pixels: the mean of the pixels' mean luminance and its error.
inline std::vector<BlockStat> block_stats(const tessera::Film& film, int edge) {
  std::vector<BlockStat> out;
  for (int by = 0; by + edge <= film.height(); by += edge)
    for (int bx = 0; bx + edge <= film.width(); bx += edge) {
      double m = 0.0, var = 0.0;
      for (int y = by; y < by + edge; ++y)
        for (int x = bx; x < bx + edge; ++x) {
          const tessera::PixelSums& p = film.at(x, y);
          const double n = static_cast<double>(p.n), pm = p.lum / n;
          m += pm;
          if (p.n > 1) var += std::fmax(0.0, (p.lum2 - p.lum * pm) / (n - 1.0)) / n;
        }
      const double np = static_cast<double>(edge * edge);
      out.push_back({m / np, std::sqrt(var) / np});
    }
  return out;
}

inline double max_block_z(const tessera::Film& a, const tessera::Film& b, int edge) {
  const std::vector<BlockStat> sa = block_stats(a, edge), sb = block_stats(b, edge);
  double z = 0.0;
  for (std::size_t i = 0; i < sa.size(); ++i) {
    const double se = std::sqrt(sa[i].se * sa[i].se + sb[i].se * sb[i].se);
    z = std::fmax(z, std::fabs(sa[i].mean - sb[i].mean) / std::fmax(se, 1e-9));
  }
  return z;
}

inline bool same_bits(const tessera::Film& a, const tessera::Film& b) {
  return a.pixels().size() == b.pixels().size() &&
         std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(tessera::PixelSums)) == 0;
}

}  // namespace gpu_test
