// Tests for SurfaceBrdf: Lambert-only sampling weight equals the albedo exactly; eval is
// reciprocal; nothing below the surface; and the sampled direction density equals pdf()
// (checked by E[cos(wi) / pdf(wi)] = pi over the hemisphere for mixed and pure lobes).
//
// Statistics: means within 4 standard errors (two-sided, 6.3e-5). Fixed seeds.
#include <catch2/catch.hpp>

#include "kernel/surface_brdf.h"
#include "sampling/rng.h"
#include "sampling/warp.h"

#include <cmath>

using tessera::Color;
using tessera::SurfaceBrdf;
using tessera::Vec3;

namespace {
Vec3 random_upper(tessera::Rng& rng, const Vec3& n) {
  const tessera::Frame f(n);
  return f.to_world(tessera::cosine_hemisphere(rng.uniform(), rng.uniform()));
}
}  // namespace

TEST_CASE("Lambert-only BRDF: sampling weight is the albedo, pdf cos/pi", "[surface_brdf]") {
  tessera::Rng rng(81, 0, 0, 0);
  const Vec3 n = glm::normalize(Vec3(0.3, -0.5, 0.8));
  const SurfaceBrdf b(n, Color(0.9, 0.5, 0.1), Color(0.0), 0.4);
  CHECK(b.p_spec == 0.0);
  double worst = 0.0;
  for (int i = 0; i < 10000; ++i) {
    const Vec3 wo = random_upper(rng, n);
    Vec3 wi;
    if (!b.sample(wo, rng.uniform(), rng.uniform(), rng.uniform(), &wi)) continue;
    const double pdf = b.pdf(wo, wi);
    worst = std::fmax(worst, glm::length(b.eval(wo, wi) / pdf - Color(0.9, 0.5, 0.1)));
    worst = std::fmax(worst, std::fabs(pdf - glm::dot(n, wi) / tessera::kPi));
  }
  CHECK(worst < 1e-12);
}

TEST_CASE("BRDF is reciprocal and zero below the surface", "[surface_brdf]") {
  tessera::Rng rng(82, 0, 0, 0);
  const Vec3 n(0.0, 0.0, 1.0);
  const SurfaceBrdf b(n, Color(0.5), Color(0.3, 0.4, 0.5), 0.35);
  double worst = 0.0;
  for (int i = 0; i < 10000; ++i) {
    const Vec3 wo = random_upper(rng, n), wi = random_upper(rng, n);
    const Color f1 = b.eval(wo, wi) / glm::dot(n, wi), f2 = b.eval(wi, wo) / glm::dot(n, wo);
    worst = std::fmax(worst, glm::length(f1 - f2) / glm::length(f1));
  }
  CHECK(worst < 1e-10);
  const Vec3 below(0.0, 0.6, -0.8);
  CHECK(tessera::is_black(b.eval(Vec3(0.0, 0.0, 1.0), below)));
  CHECK(b.pdf(Vec3(0.0, 0.0, 1.0), below) == 0.0);
}

TEST_CASE("BRDF sampling density equals pdf(): E[cos / pdf] = pi", "[surface_brdf]") {
  struct Case {
    const char* name;
    Color albedo, f0;
    double roughness;
  };
  const Case cases[] = {
      {"mixed, rough", Color(0.5), Color(0.5), 0.6},
      {"mixed, glossy", Color(0.2), Color(0.9), 0.25},
      {"specular only", Color(0.0), Color(0.8), 0.5},
  };
  tessera::Rng rng(83, 0, 0, 0);
  const Vec3 n = glm::normalize(Vec3(-0.2, 0.1, 1.0));
  for (const Case& c : cases) {
    const SurfaceBrdf b(n, c.albedo, c.f0, c.roughness);
    const Vec3 wo = glm::normalize(Vec3(0.5, 0.2, 0.7));
    constexpr int N = 200000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < N; ++i) {
      Vec3 wi;
      if (!b.sample(wo, rng.uniform(), rng.uniform(), rng.uniform(), &wi)) continue;
      const double pdf = b.pdf(wo, wi);
      if (!(pdf > 0.0)) continue;
      const double est = glm::dot(n, wi) / pdf;
      sum += est;
      sum2 += est * est;
    }
    const double mean = sum / N, se = std::sqrt(std::fmax(0.0, sum2 / N - mean * mean) / N);
    INFO(c.name << ": " << mean << " +- " << se << " vs pi");
    CHECK(std::fabs(mean - tessera::kPi) < 4.0 * se);
  }
}
