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

/// What both sampling tests check of `n` draws of e.sample() (seeded `seed`): the worst
/// disagreement of the reported pdf with pdf(wi) (relative) and of the radiance with
/// eval(wi), the failed draws (pdf 0) and those of them where the radiance is not 0, the
/// estimator luminance(L) / pdf's mean and standard error, and a histogram: bin(wi) in [0, bins).
struct SampleTally {
  std::vector<double> counts;
  double worst_pdf = 0.0, worst_L = 0.0, sum = 0.0, sum2 = 0.0;
  int n = 0, failed = 0, failed_emitting = 0;
  double mean() const { return sum / n; }
  double se() const { return std::sqrt(std::fmax(0.0, sum2 / n - mean() * mean()) / n); }
};

template <class Bin>
SampleTally tally_samples(const Environment& e, int n, std::uint64_t seed, int bins, Bin&& bin) {
  SampleTally t;
  t.counts.assign(bins, 0.0);
  t.n = n;
  tessera::Rng rng(seed, 0, 0, 0);
  for (int i = 0; i < n; ++i) {
    Vec3 wi;
    double pdf;
    const Color L = e.sample(rng.uniform(), rng.uniform(), &wi, &pdf);
    if (!(pdf > 0.0)) {
      ++t.failed;
      if (!tessera::is_black(e.eval(wi))) ++t.failed_emitting;
      continue;
    }
    t.worst_pdf = std::fmax(t.worst_pdf, std::fabs(pdf / e.pdf(wi) - 1.0));
    t.worst_L = std::fmax(t.worst_L, glm::length(L - e.eval(wi)));
    const double est = tessera::luminance(L) / pdf;
    t.sum += est;
    t.sum2 += est * est;
    t.counts[bin(wi)] += 1.0;
  }
  return t;
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
  const tessera::Frame f(glm::normalize(d.up));
  const SampleTally t = tally_samples(e, kSamples, 3, W * H, [&](const Vec3& wi) {
    const Vec3 l = f.to_local(wi);  // the texel of wi
    double phi = std::atan2(l.y, l.x);
    if (phi < 0.0) phi += 2.0 * tessera::kPi;
    const int tx = std::min(W - 1, static_cast<int>(phi / (2.0 * tessera::kPi) * W));
    const int ty = std::min(H - 1, static_cast<int>(std::acos(std::clamp(l.z, -1.0, 1.0)) / tessera::kPi * H));
    return ty * W + tx;
  });
  std::vector<double> prob(W * H);
  double wsum = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float* p = img->px(x, y);
      prob[y * W + x] = std::fmax(p[0], std::fmax(p[1], p[2])) * std::sin(tessera::kPi * (y + 0.5) / H);
      wsum += prob[y * W + x];
    }
  for (double& p : prob) p /= wsum;
  int dof = 0;
  const double chi2 = tessera_test::chi_square(t.counts, prob, kSamples - t.failed, &dof);
  INFO("chi2 " << chi2 << " dof " << dof << ", estimate " << t.mean() << " +- " << t.se() << " vs " << lum_integral
               << ", failed " << t.failed);
  CHECK(t.failed == 0);
  // sample() divides by sin(theta) of the sampled angle, pdf() by that of acos(d.n), which
  // loses digits within ~1e-5 rad of the poles: agreement to 1e-6 relative.
  CHECK(t.worst_pdf < 1e-6);
  CHECK(t.worst_L < 1e-12);
  CHECK(chi2 < tessera_test::chi2_critical(dof, tessera_test::kZ1e4));
  CHECK(std::fabs(t.mean() - lum_integral) < 4.0 * t.se());
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

namespace {

/// A gradient background's sampling against its own pdf() and eval(): the pdf integrates to 1
/// over the sphere (midpoint rule in t and phi), sample() reports pdf(wi) and eval(wi), t's
/// histogram over 32 equal bins follows the pdf (chi-square), no sample fails where the
/// radiance is not 0, and luminance(L) / pdf averages to the radiance's integral over the
/// sphere, 2 pi (top + 2 middle + bottom) / 2 per channel (t = d.up is uniform in dw / 2 pi).
void check_gradient_sampling(const BackgroundDesc& g, std::uint64_t seed) {
  const Environment e(g);
  REQUIRE(e.emits());
  const tessera::Frame f(glm::normalize(g.up));
  constexpr int kT = 2000, kPhi = 8;
  double pdf_integral = 0.0;
  for (int i = 0; i < kT; ++i) {
    const double t = -1.0 + 2.0 * (i + 0.5) / kT, r = std::sqrt(1.0 - t * t);
    for (int j = 0; j < kPhi; ++j) {
      const double phi = 2.0 * tessera::kPi * (j + 0.5) / kPhi;
      pdf_integral +=
          e.pdf(f.to_world(Vec3(r * std::cos(phi), r * std::sin(phi), t))) * (2.0 / kT) * (2.0 * tessera::kPi / kPhi);
    }
  }
  CHECK(pdf_integral == Approx(1.0).epsilon(1e-6));

  const Color integral = 2.0 * tessera::kPi * 0.5 * (g.top + 2.0 * g.middle + g.bottom) * g.intensity;
  const double lum_integral = tessera::luminance(integral);
  constexpr int kSamples = 200000, kBins = 32;
  const SampleTally t = tally_samples(e, kSamples, seed, kBins, [&](const Vec3& wi) {
    return std::min(kBins - 1, static_cast<int>((glm::dot(wi, f.n) + 1.0) * 0.5 * kBins));
  });
  std::vector<double> prob(kBins, 0.0);
  // Bin probabilities: the pdf in t integrated over each bin (fine midpoint rule)
  for (int b = 0; b < kBins; ++b) {
    constexpr int kSub = 64;
    for (int s = 0; s < kSub; ++s) {
      const double t = -1.0 + 2.0 * (b + (s + 0.5) / kSub) / kBins;
      prob[b] += e.pdf(f.to_world(Vec3(std::sqrt(1.0 - t * t), 0.0, t))) * 2.0 * tessera::kPi * (2.0 / kBins / kSub);
    }
  }
  int dof = 0;
  const double chi2 = tessera_test::chi_square(t.counts, prob, kSamples - t.failed, &dof);
  INFO("chi2 " << chi2 << " dof " << dof << ", estimate " << t.mean() << " +- " << t.se() << " vs " << lum_integral
               << ", failed " << t.failed);
  // A draw may fail only where the radiance is 0 (a black middle at t = 0 exactly)
  CHECK(t.failed_emitting == 0);
  CHECK(t.failed < 2);
  CHECK(t.worst_pdf < 1e-12);
  CHECK(t.worst_L < 1e-12);
  CHECK(chi2 < tessera_test::chi2_critical(dof, tessera_test::kZ1e4));
  // (+ the sum's rounding: where luminance is proportional to the density, no variance)
  CHECK(std::fabs(t.mean() - lum_integral) <= 4.0 * t.se() + 1e-9 * lum_integral);
}

BackgroundDesc gradient_desc(const Color& top, const Color& middle, const Color& bottom, double intensity) {
  BackgroundDesc g;
  g.type = BackgroundType::Gradient;
  g.top = top;
  g.middle = middle;
  g.bottom = bottom;
  g.up = Vec3(0.2, -0.4, 1.0);
  g.intensity = intensity;
  return g;
}

}  // namespace

TEST_CASE("gradient background: sampled in proportion to its brightness along up", "[environment]") {
  SECTION("a sky: bright top, dim bottom") {
    check_gradient_sampling(
        gradient_desc(Color(0.55, 0.65, 0.85), Color(0.25, 0.27, 0.32), Color(0.08, 0.08, 0.1), 1.0), 11);
  }
  SECTION("coloured ends whose largest components differ") {
    check_gradient_sampling(gradient_desc(Color(1.0, 0.0, 0.0), Color(0.0, 1.0, 0.0), Color(0.0, 0.0, 3.0), 2.0), 12);
  }
  SECTION("a black middle") {
    check_gradient_sampling(gradient_desc(Color(0.0, 0.5, 1.0), Color(0.0), Color(2.0, 0.1, 0.1), 1.0), 13);
  }
  SECTION("only the bottom emits: nothing is sampled above the horizon") {
    const BackgroundDesc g = gradient_desc(Color(0.0), Color(0.0), Color(0.3, 0.6, 0.9), 1.0);
    check_gradient_sampling(g, 14);
    const Environment e(g);
    Vec3 wi;
    double pdf;
    for (const double u : {0.0, 0.25, 0.5, 0.999999}) {
      e.sample(u, 0.3, &wi, &pdf);
      CHECK(glm::dot(wi, glm::normalize(g.up)) <= 0.0);
    }
    CHECK(e.pdf(glm::normalize(g.up)) == 0.0);
  }
  SECTION("equal ends: the uniform density") {
    const Environment e(gradient_desc(Color(0.4), Color(0.4), Color(0.4), 3.0));
    CHECK(e.pdf(Vec3(0.0, 1.0, 0.0)) == Approx(1.0 / (4.0 * tessera::kPi)).epsilon(1e-14));
    CHECK(e.pdf(Vec3(0.6, 0.0, 0.8)) == Approx(1.0 / (4.0 * tessera::kPi)).epsilon(1e-14));
  }
  SECTION("extreme scales") {
    // The density does not depend on the scale: 1e-300 and 1e300 sample the same directions
    const Environment tiny(gradient_desc(Color(1.0), Color(0.5), Color(0.25), 1e-300));
    const Environment huge(gradient_desc(Color(1.0), Color(0.5), Color(0.25), 1e300));
    Vec3 a, b;
    double pa, pb;
    tiny.sample(0.37, 0.61, &a, &pa);
    huge.sample(0.37, 0.61, &b, &pb);
    CHECK(a == b);
    CHECK(pa == pb);
    CHECK(pa > 0.0);
    // Colours times intensity that overflow to infinity: sampled uniformly, never a NaN pdf
    const Environment inf(gradient_desc(Color(1e300), Color(0.5), Color(0.25), 1e300));
    Vec3 d;
    double pdf;
    inf.sample(0.37, 0.61, &d, &pdf);
    CHECK(pdf == Approx(1.0 / (4.0 * tessera::kPi)));
    CHECK(inf.pdf(d) == Approx(1.0 / (4.0 * tessera::kPi)));
  }
}
