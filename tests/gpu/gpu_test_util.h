#pragma once
// What the GPU tests share: a heat-like field and scene, renders on either side, the block
// z-test (statistics in test_gpu_render.cpp's header) and a bitwise comparison of films.
//
// The same tests run twice: on a CUDA device (tessera_gpu_tests, label gpu) and, with
// TESSERA_GPU_TESTS_EMULATED defined, on the host emulation of a GPU (cuda/emulated_device.h;
// tessera_emulated_device_tests, every build, CI included), which runs the GPU backend's host
// half and its kernel's per-thread code on host threads.
#include <tessera/cuda_render.h>
#include <tessera/image.h>
#include <tessera/render.h>

#if defined(TESSERA_GPU_TESTS_EMULATED)
#include "cuda/device_render.h"
#include "cuda/emulated_device.h"
#endif

#include <catch2/catch.hpp>

#include "block_z_test.h"
#include "same_paths.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <numeric>
#include <span>
#include <thread>
#include <utility>
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

/// An equirectangular envmap of w x h texels: a smooth sky, a dark band and a bright sun
/// (texel (w / 4, h / 5)), for a background that is sampled as a light.
inline std::shared_ptr<tessera::Image> test_envmap(int w, int h) {
  auto img = std::make_shared<tessera::Image>();
  img->width = w;
  img->height = h;
  img->rgba.resize(static_cast<std::size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = img->px(x, y);
      const double u = (x + 0.5) / w, v = (y + 0.5) / h;
      const bool dark = v > 0.55 && v < 0.7;
      p[0] = dark ? 0.0f : static_cast<float>(0.4 + 0.3 * std::sin(6.0 * u));
      p[1] = dark ? 0.0f : static_cast<float>(0.5 * (1.0 - v));
      p[2] = dark ? 0.0f : static_cast<float>(0.9 * (1.0 - v) + 0.1);
      p[3] = 1.0f;
    }
  float* sun = img->px(w / 4, h / 5);
  sun[0] = 60.0f;
  sun[1] = 50.0f;
  sun[2] = 40.0f;
  return img;
}

/// Stretched coordinates of a rectilinear axis: x_i = (i / (m - 1))^p for m coordinates.
inline std::vector<double> stretched(int m, double p) {
  std::vector<double> c(static_cast<std::size_t>(m));
  for (int i = 0; i < m; ++i) c[static_cast<std::size_t>(i)] = std::pow(i / (m - 1.0), p);
  return c;
}

inline std::vector<int> all_tiles(const tessera::PreparedScene& ps) {
  std::vector<int> t(ps.tiles().size());
  std::iota(t.begin(), t.end(), 0);
  return t;
}

#if defined(TESSERA_GPU_TESTS_EMULATED)
/// The emulated device every test shares (its scenes' device copies are kept per backend).
inline const std::shared_ptr<tessera::cuda::DeviceBackend>& emulated_gpu() {
  static const std::shared_ptr<tessera::cuda::DeviceBackend> b = tessera::cuda::emulated_backend();
  return b;
}

/// A render's deadline for the tests that cut one short: far enough that prepare leaves the
/// render its time on a slow machine (the tests REQUIRE it).
inline std::chrono::steady_clock::time_point test_deadline() {
  return std::chrono::steady_clock::now() + std::chrono::seconds(4);
}

/// What a render cut short by its deadline left.
struct CutRender {
  tessera::Film film;
  tessera::RenderStats stats;
  tessera::CudaTransfer transfer;
};

/// Renders `ps` (prepared with options.deadline = `deadline`) on a fresh emulated device, one
/// sample per launch, that waits the deadline out after launch `cut_after`: the render must
/// stop there with DeadlineExceeded (checked); what it left is returned for the caller's checks.
inline CutRender render_cut_by_deadline(const tessera::PreparedScene& ps,
                                        std::chrono::steady_clock::time_point deadline, std::int64_t cut_after) {
  tessera::cuda::EmulatedDevice d;
  d.after_slice = [&](std::int64_t slices) {
    if (slices == cut_after) std::this_thread::sleep_until(deadline + std::chrono::milliseconds(10));
  };
  const auto b = tessera::cuda::emulated_backend(d);
  CutRender r{tessera::Film(ps.desc().image.width, ps.desc().image.height), {}, {}};
  tessera::CudaLaunch one;
  one.samples_per_launch = 1;
  REQUIRE(std::chrono::steady_clock::now() < deadline);  // prepare left the render its time
  CHECK_THROWS_AS(tessera::cuda::render_on_device(b, ps, all_tiles(ps), r.film, r.stats, one, &r.transfer),
                  tessera::DeadlineExceeded);
  return r;
}
#endif

/// render_tiles_cuda, or its host emulation in the emulated build.
inline void gpu_render_tiles(const tessera::PreparedScene& ps, std::span<const int> tiles, tessera::Film& film,
                             tessera::RenderStats& st, const tessera::CudaLaunch& launch = {},
                             tessera::CudaTransfer* transfer = nullptr) {
#if defined(TESSERA_GPU_TESTS_EMULATED)
  tessera::cuda::render_on_device(emulated_gpu(), ps, tiles, film, st, launch, transfer);
#else
  tessera::render_tiles_cuda(ps, tiles, film, st, launch, transfer);
#endif
}

inline tessera::Film render_gpu(const tessera::PreparedScene& ps, const tessera::CudaLaunch& launch = {},
                                tessera::CudaTransfer* transfer = nullptr, tessera::RenderStats* stats = nullptr) {
  tessera::Film film(ps.desc().image.width, ps.desc().image.height);
  tessera::RenderStats st;
  gpu_render_tiles(ps, all_tiles(ps), film, st, launch, transfer);
  if (stats) *stats = st;
  return film;
}

inline tessera::Film render_cpu(const tessera::PreparedScene& ps) {
  tessera::Film film(ps.desc().image.width, ps.desc().image.height);
  tessera::RenderStats st;
  tessera::render(ps, film, st);
  return film;
}

using tessera_test::block_stats;
using tessera_test::BlockStat;
using tessera_test::max_block_z;

/// The largest difference between two films' pixel sums relative to their size (colour,
/// alpha, luminance; 1 where a sample count differs).
inline double max_pixel_difference(const tessera::Film& a, const tessera::Film& b) {
  if (a.pixels().size() != b.pixels().size()) return 1.0;
  double d = 0.0;
  for (std::size_t i = 0; i < a.pixels().size(); ++i) {
    const tessera::PixelSums &p = a.pixels()[i], &q = b.pixels()[i];
    if (p.n != q.n || p.drawn != q.drawn) return 1.0;
    for (const auto& [x, y] : {std::pair{p.r, q.r}, {p.g, q.g}, {p.b, q.b}, {p.a, q.a}, {p.lum, q.lum}})
      d = std::fmax(d, std::fabs(x - y) / std::fmax(1.0, std::fabs(x)));
  }
  return d;
}

using tessera_test::check_same_paths;  // same_paths.h

inline bool same_bits(const tessera::Film& a, const tessera::Film& b) {
  return a.pixels().size() == b.pixels().size() &&
         std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(tessera::PixelSums)) == 0;
}

}  // namespace gpu_test
