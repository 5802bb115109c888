// Tests for RectLight and SphereLight: one-sided intersection and the documented frame;
// sample() returns the same pdf as pdf() for the direction it chose, and the sampled pdf
// integrates the light's solid angle (checked against closed forms).
//
// Statistics: means within 4 standard errors (two-sided, 6.3e-5); chi-square at 1e-4. Fixed
// seeds.
#include <catch2/catch.hpp>

#include "lights/area_lights.h"
#include "sampling/rng.h"
#include "test_support.h"

#include <cmath>
#include <vector>

using tessera::Color;
using tessera::Ray;
using tessera::RectLight;
using tessera::SphereLight;
using tessera::Vec3;

TEST_CASE("rect light: one-sided, width along u = cross(ref, n), height along v", "[area_lights]") {
  // n = -z (emits downward); ref = +y since |n.z| > 0.999: u = cross(y, -z) = -x, v = cross(n, u) = +y
  const RectLight l({Vec3(0.0), Vec3(0.0, 0.0, -1.0), 1.0, 0.5, Color(3.0)});
  const Vec3 up(0.0, 0.0, 1.0);
  CHECK(l.intersect_front(Ray{Vec3(0.45, 0.2, -1.0), up}) == Approx(1.0));
  CHECK(l.intersect_front(Ray{Vec3(0.2, 0.3, -1.0), up}) < 0.0);   // beyond half-height 0.25
  CHECK(l.intersect_front(Ray{Vec3(0.55, 0.0, -1.0), up}) < 0.0);  // beyond half-width 0.5
  CHECK(l.intersect_front(Ray{Vec3(0.0, 0.0, 1.0), -up}) < 0.0);   // the back side
  CHECK(l.intersect_front(Ray{Vec3(0.0, 0.0, -1.0), -up}) < 0.0);  // pointing away
  CHECK(l.radiance() == Color(3.0));
  // A point behind the light samples nothing
  const tessera::LightSample s = l.sample(Vec3(0.0, 0.0, 1.0), 0.3, 0.6);
  CHECK(s.pdf == 0.0);
  CHECK(tessera::is_black(s.L));
}

TEST_CASE("rect light sampling: pdf consistent, solid angle exact", "[area_lights]") {
  // Seen from a point on its axis at distance h, a rectangle of half sizes a, b subtends
  // 4 asin(a b / sqrt((a^2 + h^2)(b^2 + h^2))).
  const double a = 0.75, b = 0.4, h = 0.6;
  const RectLight l({Vec3(1.0, 2.0, 3.0), Vec3(1.0, 2.0 - h, 3.0), 2 * a, 2 * b, Color(1.0)});
  const Vec3 x(1.0, 2.0 - h, 3.0);
  const double omega = 4.0 * std::asin(a * b / std::sqrt((a * a + h * h) * (b * b + h * h)));
  tessera::Rng rng(21, 0, 0, 0);
  constexpr int n = 100000;
  double sum = 0.0, sum2 = 0.0, worst_pdf = 0.0, worst_t = 0.0;
  for (int i = 0; i < n; ++i) {
    const tessera::LightSample s = l.sample(x, rng.uniform(), rng.uniform());
    REQUIRE(s.pdf > 0.0);
    const double t = l.intersect_front(Ray{x, s.wi});
    worst_t = std::fmax(worst_t, std::fabs(t - s.dist));
    worst_pdf = std::fmax(worst_pdf, std::fabs(l.pdf(x, s.wi, t) / s.pdf - 1.0));
    sum += 1.0 / s.pdf;
    sum2 += 1.0 / (s.pdf * s.pdf);
  }
  const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
  INFO("solid angle " << omega << ", estimate " << mean << " +- " << se);
  CHECK(worst_t < 1e-12);
  CHECK(worst_pdf < 1e-9);
  CHECK(std::fabs(mean - omega) < 4.0 * se);
}

TEST_CASE("sphere light: outward-facing hit only, uniform cone sampling with a consistent pdf", "[area_lights]") {
  const SphereLight l({Vec3(0.0, 0.0, 5.0), 1.5, Color(2.0)});
  CHECK(l.intersect_front(Ray{Vec3(0.0), Vec3(0.0, 0.0, 1.0)}) == Approx(3.5));
  CHECK(l.intersect_front(Ray{Vec3(0.0), Vec3(0.0, 0.0, -1.0)}) < 0.0);
  CHECK(l.intersect_front(Ray{Vec3(0.0, 0.0, 5.0), Vec3(0.0, 0.0, 1.0)}) < 0.0);  // from inside
  CHECK(l.intersect_front(Ray{Vec3(2.0, 0.0, 0.0), Vec3(0.0, 0.0, 1.0)}) < 0.0);  // misses

  const Vec3 x(0.3, -0.2, 0.0);
  const double d = glm::length(Vec3(0.0, 0.0, 5.0) - x);
  const double cos_max = std::sqrt(1.0 - 1.5 * 1.5 / (d * d));
  const Vec3 axis = (Vec3(0.0, 0.0, 5.0) - x) / d;
  tessera::Rng rng(22, 0, 0, 0);
  constexpr int n = 100000, bins = 20;
  std::vector<double> hist(bins, 0.0);
  const std::vector<double> uniform(bins, 1.0 / bins);
  double worst_pdf = 0.0, worst_t = 0.0;
  int misses = 0;
  for (int i = 0; i < n; ++i) {
    const tessera::LightSample s = l.sample(x, rng.uniform(), rng.uniform());
    const double t = l.intersect_front(Ray{x, s.wi});
    if (t < 0.0) {
      ++misses;
    } else {
      worst_t = std::fmax(worst_t, std::fabs(t - s.dist));
    }
    worst_pdf = std::fmax(worst_pdf, std::fabs(l.pdf(x, s.wi, s.dist) / s.pdf - 1.0));
    // Uniform in solid angle over the cone: (1 - cos) / (1 - cos_max) is uniform on [0, 1)
    const double v = (1.0 - glm::dot(s.wi, axis)) / (1.0 - cos_max);
    hist[std::min(bins - 1, std::max(0, static_cast<int>(v * bins)))] += 1.0;
  }
  int dof = 0;
  const double chi2 = tessera_test::chi_square(hist, uniform, n, &dof);
  CHECK(l.pdf(x, axis, 0.0) == Approx(1.0 / (2.0 * tessera::kPi * (1.0 - cos_max))).epsilon(1e-12));
  CHECK(worst_pdf < 1e-12);
  CHECK(worst_t < 1e-9);
  CHECK(misses < n / 1000);  // only grazing rounding may miss
  INFO("chi2 " << chi2 << " dof " << dof);
  CHECK(chi2 < tessera_test::chi2_critical(dof, tessera_test::kZ1e4));
  // From inside: nothing to sample
  CHECK(l.sample(Vec3(0.0, 0.0, 5.0), 0.5, 0.5).pdf == 0.0);
}

TEST_CASE("area lights reject degenerate descriptions", "[area_lights]") {
  CHECK_THROWS_WITH(RectLight({Vec3(0.0), Vec3(0.0), 1.0, 1.0, Color(1.0)}), Catch::Contains("target"));
  CHECK_THROWS_WITH(RectLight({Vec3(0.0), Vec3(1.0), -1.0, 1.0, Color(1.0)}), Catch::Contains("size"));
  CHECK_THROWS_WITH(SphereLight({Vec3(0.0), 0.0, Color(1.0)}), Catch::Contains("radius"));
}
