// The CUDA backend against the CPU (docs/gpu.md, docs/physics.md section 10): the device
// runs the CPU's per-sample code, so its images agree with the CPU's within Monte Carlo error
// and its bits do not depend on the run or the launch configuration.
//
// Statistics: block z-tests over 36 blocks of 8x8 pixels between two independent renders
// (own seeds), each |z| < 4.2 (two-sided false-alarm probability 2.7e-5 per block, about 1e-3
// for the 36 together, Bonferroni); standard errors from each pixel's sample variance. The
// furnace: image mean within 0.5% of L and |z| < 4. Fixed seeds throughout.
#include <tessera/cuda_render.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include <cuda_runtime_api.h>

#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

namespace {

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
tessera::SceneDesc heat_scene(int n, std::uint64_t seed) {
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

std::vector<int> all_tiles(const tessera::PreparedScene& ps) {
  std::vector<int> t(ps.tiles().size());
  std::iota(t.begin(), t.end(), 0);
  return t;
}

tessera::Film render_gpu(const tessera::PreparedScene& ps, const tessera::CudaLaunch& launch = {},
                         tessera::CudaTransfer* transfer = nullptr, tessera::RenderStats* stats = nullptr) {
  tessera::Film film(ps.desc().image.width, ps.desc().image.height);
  tessera::RenderStats st;
  tessera::render_tiles_cuda(ps, all_tiles(ps), film, st, launch, transfer);
  if (stats) *stats = st;
  return film;
}

tessera::Film render_cpu(const tessera::PreparedScene& ps) {
  tessera::Film film(ps.desc().image.width, ps.desc().image.height);
  tessera::RenderStats st;
  tessera::render(ps, film, st);
  return film;
}

struct BlockStat {
  double mean, se;
};

/// Per block of edge x edge pixels: the mean of the pixels' mean luminance and its error.
std::vector<BlockStat> block_stats(const tessera::Film& film, int edge) {
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

double max_block_z(const tessera::Film& a, const tessera::Film& b, int edge) {
  const std::vector<BlockStat> sa = block_stats(a, edge), sb = block_stats(b, edge);
  double z = 0.0;
  for (std::size_t i = 0; i < sa.size(); ++i) {
    const double se = std::sqrt(sa[i].se * sa[i].se + sb[i].se * sb[i].se);
    z = std::fmax(z, std::fabs(sa[i].mean - sb[i].mean) / std::fmax(se, 1e-9));
  }
  return z;
}

bool same_bits(const tessera::Film& a, const tessera::Film& b) {
  return a.pixels().size() == b.pixels().size() &&
         std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(tessera::PixelSums)) == 0;
}

template <class T>
void check_against_cpu(tessera::DType dtype, const char* what) {
  constexpr int n = 40;
  const std::vector<T> field = heat_field<T>(n);
  const FieldView view = FieldView::contiguous(field.data(), dtype, n, n, n);
  const tessera::PreparedScene cpu_scene = tessera::prepare(view, heat_scene(n, 11));
  const tessera::PreparedScene gpu_scene = tessera::prepare(view, heat_scene(n, 12));
  const tessera::Film cpu = render_cpu(cpu_scene);
  tessera::RenderStats st;
  const tessera::Film gpu = render_gpu(gpu_scene, {}, nullptr, &st);
  const double z = max_block_z(cpu, gpu, 8);
  INFO(what << ": largest block |z| " << z << ", GPU samples " << st.samples << ", real collisions "
            << st.real_collisions);
  CHECK(st.samples == static_cast<std::uint64_t>(48 * 48 * 32));
  CHECK(st.real_collisions > 0);
  CHECK(st.discarded_samples == 0);
  CHECK(z < 4.2);
  // Same seed: the same streams, so nearly every pixel's sum agrees to rounding
  const tessera::Film gpu_same = render_gpu(cpu_scene);
  int close = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const double a = cpu.at(x, y).lum, b = gpu_same.at(x, y).lum;
      close += std::fabs(a - b) <= 1e-6 * std::fmax(1.0, std::fabs(a));
    }
  INFO(what << ": " << close << " of 2304 pixels equal to 1e-6 with the CPU's seed");
  CHECK(close >= 2304 * 9 / 10);
}

}  // namespace

TEST_CASE("GPU against CPU: heat-like scene, block z-test", "[gpu]") {
  check_against_cpu<float>(tessera::DType::Float32, "float32");
  check_against_cpu<double>(tessera::DType::Float64, "float64");
}

TEST_CASE("GPU: the same bits on every run and for any launch configuration", "[gpu]") {
  constexpr int n = 40;
  const std::vector<float> field = heat_field<float>(n);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
  const tessera::PreparedScene ps = tessera::prepare(view, heat_scene(n, 5));
  const tessera::Film a = render_gpu(ps);
  const tessera::Film b = render_gpu(ps);
  tessera::CudaLaunch odd;
  odd.block_threads = 64;
  odd.samples_per_launch = 3;
  odd.pixels_per_launch = 517;
  tessera::CudaTransfer tr;
  const tessera::Film c = render_gpu(ps, odd, &tr);
  INFO("odd launch configuration: " << tr.launches << " launches on " << tr.device_name);
  CHECK(tr.launches == 11 * 5);  // ceil(32 / 3) sample slices x ceil(2304 / 517) pixel slices
  CHECK(same_bits(a, b));
  CHECK(same_bits(a, c));
}

TEST_CASE("GPU: a managed field is read in place, with the same bits as its host copy", "[gpu]") {
  // Managed memory: prepare() reads it on the host (majorants), the kernel on the device
  constexpr int n = 40;
  const std::vector<double> field = heat_field<double>(n);
  const std::size_t bytes = field.size() * sizeof(double);
  void* managed = nullptr;
  REQUIRE(cudaMallocManaged(&managed, bytes) == cudaSuccess);
  std::memcpy(managed, field.data(), bytes);
  const tessera::SceneDesc s = heat_scene(n, 9);
  tessera::CudaTransfer host_tr, dev_tr;
  const tessera::Film from_host = render_gpu(
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float64, n, n, n), s), {}, &host_tr);
  const tessera::Film in_place =
      render_gpu(tessera::prepare(FieldView::contiguous(managed, tessera::DType::Float64, n, n, n), s), {}, &dev_tr);
  cudaFree(managed);
  INFO("copied " << host_tr.bytes_to_device << " bytes from a host field, " << dev_tr.bytes_to_device
                 << " from a managed one");
  CHECK_FALSE(host_tr.field_in_place);
  CHECK(dev_tr.field_in_place);
  CHECK(host_tr.bytes_to_device - dev_tr.bytes_to_device == bytes);
  CHECK(same_bits(from_host, in_place));
}

TEST_CASE("GPU: white furnace within 0.5%", "[gpu][furnace]") {
  constexpr int n = 5;
  constexpr double kL = 0.7;
  const std::vector<float> field(static_cast<std::size_t>(n) * n * n, 1.0f);
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (n - 1));
  s.tf.density_scale = 5.0;
  s.tf.opacity = tessera::ScalarTF::constant(1.0);
  s.tf.diffuse = tessera::ColorTF::constant(Color(1.0));
  s.camera.position = Vec3(1.3, 0.8, -2.2);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 32.0;
  s.background.color = Color(kL);
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 100000;
  s.integrator.shading = tessera::Shading::Phase;
  s.integrator.phase_g = 0.3;
  s.integrator.macrocell = 2;
  s.image = {32, 32, 256, 0.0};
  s.options.seed = 77;
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n), s);
  tessera::RenderStats st;
  const tessera::Film film = render_gpu(ps, {}, nullptr, &st);
  double sum = 0.0, sum2 = 0.0, count = 0.0;
  for (const tessera::PixelSums& p : film.pixels()) {
    sum += p.lum;
    sum2 += p.lum2;
    count += static_cast<double>(p.n);
  }
  const double mean = sum / count, se = std::sqrt(std::fmax(0.0, sum2 / count - mean * mean) / count);
  INFO("mean " << mean << " +- " << se << ", real collisions " << st.real_collisions);
  CHECK(st.real_collisions > 0);
  CHECK(std::fabs(mean - kL) < 0.005 * kL);
  CHECK(std::fabs(mean - kL) < 4.0 * se + 1e-12);
}

TEST_CASE("GPU: what the backend does not cover is refused by name", "[gpu]") {
  constexpr int n = 8;
  const std::vector<std::int16_t> field(static_cast<std::size_t>(n) * n * n, 3);
  tessera::SceneDesc s = heat_scene(n, 1);
  s.tf.lo = 0.0;
  s.tf.hi = 10.0;
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Int16, n, n, n), s);
  tessera::Film film(48, 48);
  tessera::RenderStats st;
  CHECK_THROWS_WITH(tessera::render_tiles_cuda(ps, all_tiles(ps), film, st),
                    Catch::Contains("int16") && Catch::Contains("not supported on the GPU"));
}
