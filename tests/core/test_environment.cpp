// Tests for Environment: constant and gradient evaluation, the envmap's direction <-> texel
// mapping, and its importance sampling (pdf integrates to 1, sample() agrees with pdf() and
// eval(), texels are chosen in proportion to their weight, the NEE estimator is unbiased).
//
// Statistics: chi-square at significance 1e-4 (Wilson-Hilferty), means within 4 standard
// errors (two-sided, 6.3e-5). Fixed seeds.
#include <catch2/catch.hpp>

#include "lights/environment.h"
#include "sampling/rng.h"
#include "sampling/warp.h"
#include "test_support.h"

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

using tessera::BackgroundDesc;
using tessera::BackgroundType;
using tessera::Color;
using tessera::Environment;
using tessera::Vec3;

namespace {

std::shared_ptr<tessera::Image> random_envmap(int w, int h, std::uint64_t seed) {
  auto img = std::make_shared<tessera::Image>();
  img->width = w;
  img->height = h;
  img->rgba.resize(static_cast<std::size_t>(w) * h * 4);
  tessera::Rng rng(seed, 0, 0, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = img->px(x, y);
      const bool dark = rng.uniform() < 0.15;
      for (int c = 0; c < 3; ++c) p[c] = dark ? 0.0f : static_cast<float>(rng.uniform() * 2.0);
      p[3] = 1.0f;
    }
  img->px(3, 1)[0] = 50.0f;  // a sun
  return img;
}

/// Direction of the centre of texel (x, y) in the frame around `up`.
Vec3 texel_direction(const Vec3& up, int x, int y, int w, int h, double fx = 0.5, double fy = 0.5) {
  const double theta = tessera::kPi * (y + fy) / h, phi = 2.0 * tessera::kPi * (x + fx) / w;
  const tessera::Frame f(glm::normalize(up));
  return f.to_world(Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
}

}  // namespace

TEST_CASE("constant and gradient backgrounds", "[environment]") {
  BackgroundDesc d;
  d.color = Color(0.2, 0.4, 0.6);
  d.intensity = 2.0;
  const Environment c(d);
  CHECK(c.eval(Vec3(0.0, 1.0, 0.0)) == Color(0.4, 0.8, 1.2));
  CHECK(c.pdf(Vec3(1.0, 0.0, 0.0)) == Approx(1.0 / (4.0 * tessera::kPi)));
  CHECK(c.emits());
  Vec3 wi;
  double pdf;
  const Color L = c.sample(0.3, 0.7, &wi, &pdf);
  CHECK(L == Color(0.4, 0.8, 1.2));
  CHECK(pdf == Approx(1.0 / (4.0 * tessera::kPi)));
  CHECK(glm::length(wi) == Approx(1.0));

  d.color = Color(0.0);
  CHECK_FALSE(Environment(d).emits());

  BackgroundDesc g;
  g.type = BackgroundType::Gradient;
  g.top = Color(1.0, 0.0, 0.0);
  g.middle = Color(0.0, 1.0, 0.0);
  g.bottom = Color(0.0, 0.0, 1.0);
  g.up = Vec3(0.0, 2.0, 0.0);  // not unit: normalised
  g.visible = false;
  const Environment e(g);
  CHECK_FALSE(e.visible());
  CHECK(e.emits());
  CHECK(glm::length(e.eval(Vec3(0.0, 1.0, 0.0)) - g.top) < 1e-15);
  CHECK(glm::length(e.eval(Vec3(0.0, -1.0, 0.0)) - g.bottom) < 1e-15);
  CHECK(glm::length(e.eval(Vec3(1.0, 0.0, 0.0)) - g.middle) < 1e-15);
  const double s = std::sqrt(0.5);
  CHECK(glm::length(e.eval(Vec3(s, s, 0.0)) - Color(s, 1.0 - s, 0.0)) < 1e-15);
}

TEST_CASE("envmap: texel mapping, row 0 at the up pole", "[environment]") {
  const auto img = random_envmap(8, 4, 1);
  BackgroundDesc d;
  d.type = BackgroundType::EnvMap;
  d.envmap = img;
  d.up = Vec3(0.0, 1.0, 0.0);
  d.intensity = 0.5;
  const Environment e(d);
  bool ok = true;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      const Color want = Color(img->px(x, y)[0], img->px(x, y)[1], img->px(x, y)[2]) * 0.5;
      for (const double fx : {0.05, 0.5, 0.95}) ok = ok && e.eval(texel_direction(d.up, x, y, 8, 4, fx, 0.5)) == want;
    }
  CHECK(ok);
  const Color pole = Color(img->px(0, 0)[0], img->px(0, 0)[1], img->px(0, 0)[2]) * 0.5;
  // Straight up lies in row 0 (phi is 0 there by atan2(0, 0))
  CHECK(e.eval(Vec3(0.0, 1.0, 0.0)) == pole);
}

TEST_CASE("envmap importance sampling: pdf integrates to 1, matches sample(), unbiased", "[environment]") {
  constexpr int W = 8, H = 4;
  const auto img = random_envmap(W, H, 2);
  BackgroundDesc d;
  d.type = BackgroundType::EnvMap;
  d.envmap = img;
  d.up = Vec3(0.3, 0.2, 1.0);
  const Environment e(d);
  REQUIRE(e.emits());

  // Integral of pdf and of radiance over the sphere, midpoint rule in (theta, phi), 32 x 32
  // points per texel (pdf and radiance are piecewise constant on texels).
  double pdf_integral = 0.0, lum_integral = 0.0;
  const int sx = 32, sy = 32;
  for (int y = 0; y < H * sy; ++y) {
    const double theta = tessera::kPi * (y + 0.5) / (H * sy);
    const double dtheta = tessera::kPi / (H * sy), dphi = 2.0 * tessera::kPi / (W * sx);
    for (int x = 0; x < W * sx; ++x) {
      const Vec3 dir = texel_direction(d.up, x, y, W * sx, H * sy);
      const double dw = std::sin(theta) * dtheta * dphi;
      pdf_integral += e.pdf(dir) * dw;
      lum_integral += tessera::luminance(e.eval(dir)) * dw;
    }
  }
  CHECK(pdf_integral == Approx(1.0).epsilon(1e-9));

  // Sampling: pdf and radiance agree with pdf()/eval(); texel frequencies follow the
  // sampling weights; the estimator luminance(L) / pdf has mean = integral of luminance.
  constexpr int kSamples = 200000;
  tessera::Rng rng(3, 0, 0, 0);
  std::vector<double> counts(W * H, 0.0), prob(W * H);
  double worst_pdf = 0.0, worst_L = 0.0, sum = 0.0, sum2 = 0.0;
  int failed = 0;
  for (int i = 0; i < kSamples; ++i) {
    Vec3 wi;
    double pdf;
    const Color L = e.sample(rng.uniform(), rng.uniform(), &wi, &pdf);
    if (!(pdf > 0.0)) {
      ++failed;
      continue;
    }
    worst_pdf = std::fmax(worst_pdf, std::fabs(pdf / e.pdf(wi) - 1.0));
    worst_L = std::fmax(worst_L, glm::length(L - e.eval(wi)));
    const double est = tessera::luminance(L) / pdf;
    sum += est;
    sum2 += est * est;
    // Texel of wi
    const tessera::Frame f(glm::normalize(d.up));
    const Vec3 l = f.to_local(wi);
    double phi = std::atan2(l.y, l.x);
    if (phi < 0.0) phi += 2.0 * tessera::kPi;
    const int tx = std::min(W - 1, static_cast<int>(phi / (2.0 * tessera::kPi) * W));
    const int ty = std::min(H - 1, static_cast<int>(std::acos(std::clamp(l.z, -1.0, 1.0)) / tessera::kPi * H));
    counts[ty * W + tx] += 1.0;
  }
  double wsum = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float* p = img->px(x, y);
      prob[y * W + x] = std::fmax(p[0], std::fmax(p[1], p[2])) * std::sin(tessera::kPi * (y + 0.5) / H);
      wsum += prob[y * W + x];
    }
  for (double& p : prob) p /= wsum;
  int dof = 0;
  const double chi2 = tessera_test::chi_square(counts, prob, kSamples - failed, &dof);
  const double mean = sum / kSamples;
  const double se = std::sqrt(std::fmax(0.0, sum2 / kSamples - mean * mean) / kSamples);
  INFO("chi2 " << chi2 << " dof " << dof << ", estimate " << mean << " +- " << se << " vs " << lum_integral
               << ", failed " << failed);
  CHECK(failed == 0);
  // sample() divides by sin(theta) of the sampled angle, pdf() by that of acos(d.n), which
  // loses digits within ~1e-5 rad of the poles: agreement to 1e-6 relative.
  CHECK(worst_pdf < 1e-6);
  CHECK(worst_L < 1e-12);
  CHECK(chi2 < tessera_test::chi2_critical(dof, tessera_test::kZ1e4));
  CHECK(std::fabs(mean - lum_integral) < 4.0 * se);
}

TEST_CASE("environment rejects bad envmaps and intensities", "[environment]") {
  BackgroundDesc d;
  d.type = BackgroundType::EnvMap;
  CHECK_THROWS_WITH(Environment(d), Catch::Contains("no image"));
  auto img = random_envmap(4, 2, 3);
  img->px(2, 1)[1] = std::numeric_limits<float>::quiet_NaN();
  d.envmap = img;
  CHECK_THROWS_WITH(Environment(d), Catch::Contains("(2, 1)"));
  BackgroundDesc c;
  c.intensity = -1.0;
  CHECK_THROWS_WITH(Environment(c), Catch::Contains("intensity"));
}
