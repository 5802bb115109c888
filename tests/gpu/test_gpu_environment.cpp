// The background's lookups on the GPU against the host's (docs/gpu.md): Environment::sample,
// pdf and eval have one definition for both (lights/environment_eval.h), so for the same inputs
// the device's directions and pdfs equal the host's to rounding (nvcc may fuse a multiply and
// an add) and its texels are the host's, but where a direction lies on a texel's edge.
#include "env_probe.h"
#include "gpu_test_util.h"

#include <tessera/cuda_render.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

using tessera::Color;
using tessera::Vec3;

namespace {

double rel(double a, double b) { return std::fabs(a - b) / std::fmax(1e-300, std::fmax(std::fabs(a), std::fabs(b))); }
/// Colours equal to rounding: a gradient's mix may take a fused multiply-add on the device
bool near(const Color& a, const Color& b) {
  return rel(a.x, b.x) <= 1e-12 && rel(a.y, b.y) <= 1e-12 && rel(a.z, b.z) <= 1e-12;
}

void compare(const tessera::BackgroundDesc& desc, const char* what) {
  const tessera::Environment env(desc);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<gpu_test::EnvProbe> in(8192);
  for (auto& p : in) {
    p.u1 = u(rng);
    p.u2 = u(rng);
    const double z = 2.0 * u(rng) - 1.0, phi = 2.0 * tessera::kPi * u(rng), r = std::sqrt(std::fmax(0.0, 1.0 - z * z));
    p.look = Vec3(r * std::cos(phi), r * std::sin(phi), z);
  }
  const std::vector<gpu_test::EnvProbe> dev = gpu_test::probe_environment_on_device(env, in);
  int dir_off = 0, pdf_off = 0, pdf_d_off = 0, sampled_off = 0, eval_d_off = 0, look_off = 0;
  double worst_dir = 0.0, worst_pdf = 0.0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    gpu_test::EnvProbe h = in[i];
    gpu_test::run_probe(env, h);
    const gpu_test::EnvProbe& g = dev[i];
    const double dd = glm::length(h.d - g.d);
    worst_dir = std::fmax(worst_dir, dd);
    dir_off += !(dd <= 1e-12);
    const double rp = rel(h.pdf, g.pdf);
    worst_pdf = std::fmax(worst_pdf, rp);
    pdf_off += !(rp <= 1e-9);
    pdf_d_off += !(rel(h.pdf_of_d, g.pdf_of_d) <= 1e-9);
    sampled_off += !near(h.sampled, g.sampled);
    eval_d_off += !near(h.eval_d, g.eval_d);
    look_off += !near(h.eval_look, g.eval_look);
  }
  INFO(what << ": of " << in.size() << " probes, direction off " << dir_off << " (largest " << worst_dir
            << "), pdf off " << pdf_off << " (largest rel. " << worst_pdf << "), pdf of the direction off " << pdf_d_off
            << ", sampled radiance off " << sampled_off << ", eval of the direction off " << eval_d_off
            << ", eval of a given direction off " << look_off);
  // A texel's edge within rounding of a direction: a few in 8192 at most
  CHECK(dir_off == 0);
  CHECK(pdf_off <= 4);
  CHECK(pdf_d_off <= 4);
  CHECK(sampled_off <= 4);
  CHECK(eval_d_off <= 4);
  CHECK(look_off <= 4);
}

}  // namespace

TEST_CASE("GPU: the background's sample, pdf and eval equal the host's", "[gpu]") {
  tessera::BackgroundDesc env;
  env.type = tessera::BackgroundType::EnvMap;
  env.envmap = gpu_test::test_envmap(32, 16);
  env.up = Vec3(0.2, 1.0, 0.1);
  env.intensity = 1.5;
  compare(env, "envmap, tilted");
  env.up = Vec3(0.0, 0.0, 1.0);
  compare(env, "envmap, up z");
  tessera::BackgroundDesc grad;
  grad.type = tessera::BackgroundType::Gradient;
  grad.top = Color(1.0, 0.9, 0.8);
  grad.middle = Color(0.2, 0.3, 0.4);
  grad.bottom = Color(0.05, 0.0, 0.1);
  grad.up = Vec3(0.3, 0.2, 1.0);
  compare(grad, "gradient");
}

TEST_CASE("GPU: a 1D distribution's samples are the host's", "[gpu]") {
  // Bins with zeros among them (skipped), a tall one, and many: the envmap's marginal's shape
  std::vector<double> f(37);
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = (i % 5 == 2) ? 0.0 : 1.0 + std::sin(0.7 * i);
  f[11] = 60.0;
  std::vector<double> table(2 * f.size() + 2);  // Distribution1D's layout
  tessera::detail::build_distribution(f.data(), f.size(), table.data());
  const tessera::Distribution1DView v = tessera::detail::distribution_at(table.data(), f.size());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<gpu_test::DistProbe> in(4096);
  for (auto& p : in) p.u = u(rng);
  in[0].u = 0.0;
  in[1].u = v.cdf[11];
  const std::vector<gpu_test::DistProbe> dev = gpu_test::probe_distribution_on_device(table, f.size(), in);
  int bin_off = 0, lib_off = 0, x_off = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    gpu_test::DistProbe h = in[i];
    gpu_test::run_probe(v, h);
    bin_off += h.bin != dev[i].bin;
    lib_off += h.bin_lib != dev[i].bin_lib;
    x_off += !(rel(h.x, dev[i].x) <= 1e-12);
  }
  INFO("of " << in.size() << ": bin off " << bin_off << ", std::upper_bound's off " << lib_off << ", x off " << x_off);
  CHECK(bin_off == 0);
  CHECK(x_off == 0);
  // std::upper_bound compiled for the device (libstdc++ 12 under nvcc 13's relaxed constexpr)
  // picked other bins for 3829 of these 4096 on an H200: device code never calls the
  // library's search algorithms (distribution.h has its own); reported, not required
  if (lib_off != 0)
    WARN("std::upper_bound in device code disagrees with the host for " << lib_off << " of " << in.size());
}
