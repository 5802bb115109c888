// The CUDA backend against the CPU (docs/gpu.md, docs/physics.md section 10): the device
// runs the CPU's per-sample code, so its images agree with the CPU's within Monte Carlo error
// and its bits do not depend on the run or the launch configuration.
//
// Statistics: block z-tests over 36 blocks of 8x8 pixels between two independent renders
// (own seeds), each |z| < 4.2 (two-sided false-alarm probability 2.7e-5 per block, about 1e-3
// for the 36 together, Bonferroni); standard errors from each pixel's sample variance. The
// furnace: image mean within 0.5% of L and |z| < 4. Fixed seeds throughout.
#include "gpu_test_util.h"

#include <tessera/brick_cache.h>
#include <tessera/cuda_render.h>
#include <tessera/field_summary.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#if !defined(TESSERA_GPU_TESTS_EMULATED)
#include <cuda_runtime_api.h>
#endif

#include <cmath>
#include <cstring>
#include <functional>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

using namespace gpu_test;

namespace {

/// heat_scene of seed `seed`, changed by `edit` when given.
tessera::SceneDesc edited_heat_scene(int n, std::uint64_t seed, const std::function<void(tessera::SceneDesc&)>& edit) {
  tessera::SceneDesc s = heat_scene(n, seed);
  if (edit) edit(s);
  return s;
}

/// Returns the GPU's counters of the render with the CPU's seed.
template <class T>
tessera::RenderStats check_against_cpu(tessera::DType dtype, const char* what,
                                       const std::function<void(tessera::SceneDesc&)>& edit = {}) {
  constexpr int n = 40;
  const std::vector<T> field = heat_field<T>(n);
  const FieldView view = FieldView::contiguous(field.data(), dtype, n, n, n);
  const tessera::PreparedScene cpu_scene = tessera::prepare(view, edited_heat_scene(n, 11, edit));
  const tessera::PreparedScene gpu_scene = tessera::prepare(view, edited_heat_scene(n, 12, edit));
  const tessera::Film cpu = render_cpu(cpu_scene);
  tessera::RenderStats st;
  const tessera::Film gpu = render_gpu(gpu_scene, {}, nullptr, &st);
  const double z = max_block_z(cpu, gpu, 8);
  INFO(what << ": largest block |z| " << z << ", GPU samples " << st.samples << ", real collisions "
            << st.real_collisions);
  if (gpu_scene.desc().image.target_error == 0.0) CHECK(st.samples == static_cast<std::uint64_t>(48 * 48 * 32));
  CHECK(st.real_collisions > 0);
  CHECK(st.discarded_samples == 0);
  CHECK(z < 4.2);
  // Same seed: the same streams, so nearly every pixel's sum agrees to rounding
  tessera::RenderStats cpu_st, gpu_st;
  {
    tessera::Film f(48, 48);
    tessera::render(cpu_scene, f, cpu_st);
  }
  const tessera::Film gpu_same = render_gpu(cpu_scene, {}, nullptr, &gpu_st);
  // ... and the same paths: every counter equal
  CHECK(gpu_st.samples == cpu_st.samples);
  CHECK(gpu_st.free_flight_lookups == cpu_st.free_flight_lookups);
  CHECK(gpu_st.transmittance_lookups == cpu_st.transmittance_lookups);
  CHECK(gpu_st.gradient_lookups == cpu_st.gradient_lookups);
  CHECK(gpu_st.real_collisions == cpu_st.real_collisions);
  CHECK(gpu_st.null_collisions == cpu_st.null_collisions);
  int close = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const double a = cpu.at(x, y).lum, b = gpu_same.at(x, y).lum;
      close += std::fabs(a - b) <= 1e-6 * std::fmax(1.0, std::fabs(a));
    }
  INFO(what << ": " << close << " of 2304 pixels equal to 1e-6 with the CPU's seed");
  CHECK(close >= 2304 * 9 / 10);
  return gpu_st;
}

}  // namespace

TEST_CASE("GPU against CPU: heat-like scene, block z-test", "[gpu]") {
  check_against_cpu<float>(tessera::DType::Float32, "float32");
  check_against_cpu<double>(tessera::DType::Float64, "float64");
}

TEST_CASE("GPU against CPU: an envmap background, sampled as a light", "[gpu]") {
  // The envmap's texels and sampling table are copied with the scene: camera rays that leave
  // the volume read the texels, next-event estimation samples the table, MIS reads its pdf
  check_against_cpu<double>(tessera::DType::Float64, "envmap", [](tessera::SceneDesc& s) {
    s.background = {};
    s.background.type = tessera::BackgroundType::EnvMap;
    s.background.envmap = test_envmap(32, 16);
    s.background.up = Vec3(0.2, 1.0, 0.1);
    s.background.intensity = 1.5;
  });
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

#if !defined(TESSERA_GPU_TESTS_EMULATED)  // (the emulated device: test_emulated_device.cpp)
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
#endif

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

TEST_CASE("GPU against CPU: adaptive sampling", "[gpu]") {
  // Each pixel's count comes from its block neighbours' pilot samples, as on the CPU: the
  // same seed gives the same counts (samples and lookups equal), another seed an image that
  // passes the block z-test
  const tessera::RenderStats st =
      check_against_cpu<double>(tessera::DType::Float64, "adaptive", [](tessera::SceneDesc& s) {
        s.image.spp = 64;
        s.image.target_error = 0.08;
      });
  // ... and the counts vary: fewer samples than uniform sampling, more than the pilots
  INFO("samples " << st.samples);
  CHECK(st.samples < std::uint64_t{48 * 48 * 64} * 3 / 4);
  CHECK(st.samples > std::uint64_t{48 * 48 * 8});
}
