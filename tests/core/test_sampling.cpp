// Tests for the sampling helpers: Distribution1D / 2D pdfs integrate to 1, sampled points land
// in bins in proportion to f and report the pdf they were drawn with; the ziggurat's Exp(1)
// variates follow the exponential law in every layer, wedge and the tail; warps land in their
// domains with the documented density; the power heuristic's weights sum to 1; random streams
// are pure functions of their four keys.
//
// Statistics: chi-square tests at significance 1e-4 (Wilson-Hilferty critical value), means
// within 4 standard errors. Fixed seeds.
#include <catch2/catch.hpp>

#include "kernel/path_tracer.h"
#include "sampling/distribution.h"
#include "sampling/exponential.h"
#include "sampling/rng.h"
#include "sampling/warp.h"
#include "test_support.h"

#include <cmath>
#include <set>
#include <vector>

using tessera::Distribution1D;
using tessera::Distribution2D;
using tessera::Rng;

TEST_CASE("Distribution1D: pdf integrates to 1, samples follow f, zero bins are never hit", "[sampling]") {
  Rng rng(11, 0, 0, 0);
  const std::vector<std::vector<double>> fs = {
      {1.0},
      {0.0, 3.0, 1.0, 0.0, 0.0, 6.0, 2.0},
      {5.0, 0.0, 0.0, 0.0},
      {0.0, 0.0, 0.0, 1e-3},
  };
  for (const auto& f : fs) {
    const Distribution1D d(f.data(), f.size());
    double fsum = 0.0, pdf_integral = 0.0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      fsum += f[i];
      pdf_integral += d.pdf(i) / static_cast<double>(f.size());
    }
    CHECK(pdf_integral == Approx(1.0).epsilon(1e-14));
    CHECK(d.integral() == Approx(fsum / f.size()).epsilon(1e-14));

    constexpr int kSamples = 100000;
    std::vector<double> counts(f.size(), 0.0), prob(f.size());
    bool bin_consistent = true;
    for (int s = 0; s < kSamples; ++s) {
      std::size_t bin;
      const double x = d.sample(rng.uniform(), &bin);
      bin_consistent = bin_consistent && x >= 0.0 && x < 1.0 && static_cast<std::size_t>(x * f.size()) == bin;
      counts[bin] += 1.0;
    }
    for (std::size_t i = 0; i < f.size(); ++i) prob[i] = f[i] / fsum;
    bool zero_bins_empty = true;
    for (std::size_t i = 0; i < f.size(); ++i) zero_bins_empty = zero_bins_empty && (f[i] > 0.0 || counts[i] == 0.0);
    CHECK(bin_consistent);
    CHECK(zero_bins_empty);
    if (f.size() > 1) {
      int dof = 0;
      const double chi2 = tessera_test::chi_square(counts, prob, kSamples, &dof);
      if (dof > 0) CHECK(chi2 < tessera_test::chi2_critical(dof, tessera_test::kZ1e4));
    }
  }
  // Extreme u never escapes [0, 1) nor lands on an empty bin
  const std::vector<double> f = {0.0, 2.0, 0.0};
  const Distribution1D d(f.data(), f.size());
  for (const double u : {0.0, 1e-300, 0.5, 1.0 - 1e-16, std::nextafter(1.0, 0.0)}) {
    std::size_t bin;
    const double x = d.sample(u, &bin);
    CHECK(bin == 1);
    CHECK(x >= 1.0 / 3.0);
    CHECK(x < 2.0 / 3.0 + 1e-15);
  }
  // All-zero f: uniform
  const std::vector<double> z(4, 0.0);
  const Distribution1D dz(z.data(), z.size());
  CHECK(dz.pdf(2) == 1.0);
  std::size_t bin;
  CHECK(dz.sample(0.6, &bin) == Approx(0.6));
  CHECK(bin == 2);
}

TEST_CASE("Distribution2D: pdf integrates to 1, sample() returns pdf(x, y), bins follow f", "[sampling]") {
  Rng rng(12, 0, 0, 0);
  constexpr std::size_t nx = 8, ny = 5;
  std::vector<double> f(nx * ny);
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = rng.uniform() < 0.2 ? 0.0 : rng.uniform() * 3.0;
  f[3] = 40.0;                                               // a hot spot
  for (std::size_t x = 0; x < nx; ++x) f[2 * nx + x] = 0.0;  // an empty row
  const Distribution2D d(f, nx, ny);
  double fsum = 0.0;
  for (const double v : f) fsum += v;
  CHECK(d.integral() == Approx(fsum / (nx * ny)).epsilon(1e-13));

  double pdf_integral = 0.0;
  for (std::size_t y = 0; y < ny; ++y)
    for (std::size_t x = 0; x < nx; ++x)
      pdf_integral += d.pdf((x + 0.5) / nx, (y + 0.5) / ny) / static_cast<double>(nx * ny);
  CHECK(pdf_integral == Approx(1.0).epsilon(1e-13));

  constexpr int kSamples = 200000;
  std::vector<double> counts(nx * ny, 0.0), prob(nx * ny);
  double worst = 0.0;
  for (int s = 0; s < kSamples; ++s) {
    double x, y;
    const double pdf = d.sample(rng.uniform(), rng.uniform(), &x, &y);
    worst = std::fmax(worst, std::fabs(pdf - d.pdf(x, y)));
    const std::size_t bx = std::min(nx - 1, static_cast<std::size_t>(x * nx));
    const std::size_t by = std::min(ny - 1, static_cast<std::size_t>(y * ny));
    counts[by * nx + bx] += 1.0;
  }
  for (std::size_t i = 0; i < f.size(); ++i) prob[i] = f[i] / fsum;
  CHECK(worst < 1e-12);
  bool zero_bins_empty = true;
  for (std::size_t i = 0; i < f.size(); ++i) zero_bins_empty = zero_bins_empty && (f[i] > 0.0 || counts[i] == 0.0);
  CHECK(zero_bins_empty);
  int dof = 0;
  const double chi2 = tessera_test::chi_square(counts, prob, kSamples, &dof);
  INFO("chi2 " << chi2 << " dof " << dof);
  CHECK(chi2 < tessera_test::chi2_critical(dof, tessera_test::kZ1e4));
}

TEST_CASE("power heuristic weights of two strategies sum to 1", "[sampling]") {
  Rng rng(13, 0, 0, 0);
  double worst = 0.0;
  for (int i = 0; i < 10000; ++i) {
    const double a = std::exp(20.0 * rng.uniform() - 10.0), b = std::exp(20.0 * rng.uniform() - 10.0);
    worst = std::fmax(worst, std::fabs(tessera::power_heuristic(a, b) + tessera::power_heuristic(b, a) - 1.0));
  }
  CHECK(worst < 1e-14);
  CHECK(tessera::power_heuristic(2.0, 1.0) == Approx(0.8).epsilon(1e-15));
  CHECK(tessera::power_heuristic(1.0, 0.0) == 1.0);
  CHECK(tessera::power_heuristic(0.0, 1.0) == 0.0);
  CHECK(tessera::power_heuristic(0.0, 0.0) == 0.0);
}

TEST_CASE("exp_unit: the ziggurat draws Exp(1) in every layer, wedge and the tail", "[sampling]") {
  namespace d = tessera::detail;
  // The layers' edges X_i (X_256 = 0): each layer interval [X_{i+1}, X_i) gets mass from the
  // cores of the wider layers and from layer i's wedge, so a wrong table or wedge test shows
  // in its bin; the tail beyond r in three bins of its own
  std::vector<double> edges;  // decreasing, from r down to 0
  for (int i = 1; i < 256; ++i) edges.push_back(d::kExpZigguratW[i] * 0x1.0p53);
  edges.push_back(0.0);
  const double r = d::kExpZigguratR;
  CHECK(edges.front() == Approx(r).epsilon(1e-15));
  for (std::size_t i = 1; i < edges.size(); ++i) REQUIRE(edges[i] < edges[i - 1]);
  // Bins: [0, X_255), ..., [X_2, r), then [r, r + 1), [r + 1, r + 2), [r + 2, inf)
  std::vector<double> lo, hi;
  for (std::size_t i = edges.size() - 1; i > 0; --i) lo.push_back(edges[i]), hi.push_back(edges[i - 1]);
  lo.insert(lo.end(), {r, r + 1.0, r + 2.0});
  hi.insert(hi.end(), {r + 1.0, r + 2.0, INFINITY});
  std::vector<double> prob(lo.size()), count(lo.size(), 0.0);
  for (std::size_t b = 0; b < lo.size(); ++b) prob[b] = std::exp(-lo[b]) - (hi[b] < INFINITY ? std::exp(-hi[b]) : 0.0);
  // 64 equiprobable bins as well: F^-1(k / 64) = -log(1 - k / 64)
  std::vector<double> eq(64, 0.0);
  Rng rng(21, 0, 0, 0);
  constexpr int n = 4000000;
  double sum = 0.0, sum2 = 0.0, tail_sum = 0.0;
  int tail = 0;
  bool finite = true;
  for (int i = 0; i < n; ++i) {
    const double x = tessera::exp_unit(rng);
    finite = finite && std::isfinite(x) && x >= 0.0;
    sum += x;
    sum2 += x * x;
    if (x >= r) ++tail, tail_sum += x - r;
    const auto b = std::upper_bound(hi.begin(), hi.end(), x) - hi.begin();  // first bin whose hi > x
    count[static_cast<std::size_t>(std::min<std::ptrdiff_t>(b, static_cast<std::ptrdiff_t>(hi.size()) - 1))] += 1.0;
    eq[static_cast<std::size_t>(std::min(63.0, std::floor(-std::expm1(-x) * 64.0)))] += 1.0;
  }
  REQUIRE(finite);
  int dof = 0;
  const double chi2_layers = tessera_test::chi_square(count, prob, n, &dof);
  INFO("layer bins: chi2 " << chi2_layers << " on " << dof << " dof");
  CHECK(chi2_layers < tessera_test::chi2_critical(dof, tessera_test::kZ1e4));
  const double chi2_eq = tessera_test::chi_square(eq, std::vector<double>(64, 1.0 / 64.0), n, &dof);
  INFO("equiprobable bins: chi2 " << chi2_eq << " on " << dof << " dof");
  CHECK(chi2_eq < tessera_test::chi2_critical(dof, tessera_test::kZ1e4));
  // Mean 1 and E x^2 = 2 (the sd of the mean of x^2: sqrt((E x^4 - 4) / n) = sqrt(20 / n))
  CHECK(std::fabs(sum / n - 1.0) < 4.0 / std::sqrt(double(n)));
  CHECK(std::fabs(sum2 / n - 2.0) < 4.0 * std::sqrt(20.0 / n));
  // The tail: P(x >= r) = exp(-r), and beyond r the excess is again Exp(1)
  const double p_tail = std::exp(-r);
  CHECK(std::fabs(tail - n * p_tail) < 4.0 * std::sqrt(n * p_tail));
  REQUIRE(tail > 100);
  CHECK(std::fabs(tail_sum / tail - 1.0) < 4.0 / std::sqrt(double(tail)));
}

TEST_CASE("warps land in their domains with the documented densities", "[sampling]") {
  Rng rng(14, 0, 0, 0);
  constexpr int n = 100000;
  double disk_r2 = 0.0, sphere_z = 0.0, sphere_z2 = 0.0, hemi_z = 0.0;
  bool in_disk = true, unit_sphere = true, upper = true;
  for (int i = 0; i < n; ++i) {
    const tessera::Vec2 p = tessera::concentric_disk(rng.uniform(), rng.uniform());
    in_disk = in_disk && glm::dot(p, p) <= 1.0 + 1e-12;
    disk_r2 += glm::dot(p, p);
    const tessera::Vec3 s = tessera::uniform_sphere(rng.uniform(), rng.uniform());
    unit_sphere = unit_sphere && std::fabs(glm::length(s) - 1.0) < 1e-12;
    sphere_z += s.z;
    sphere_z2 += s.z * s.z;
    const tessera::Vec3 h = tessera::cosine_hemisphere(rng.uniform(), rng.uniform());
    upper = upper && h.z >= 0.0 && std::fabs(glm::length(h) - 1.0) < 1e-12;
    hemi_z += h.z;
  }
  CHECK(in_disk);
  CHECK(unit_sphere);
  CHECK(upper);
  // Uniform disk: E[r^2] = 1/2, sd of r^2 = 1/sqrt(12). Uniform sphere: E[z] = 0, E[z^2] = 1/3.
  // Cosine hemisphere: E[cos] = 2/3, var = 1/2 - 4/9 = 1/18.
  CHECK(std::fabs(disk_r2 / n - 0.5) < 4.0 / std::sqrt(12.0 * n));
  CHECK(std::fabs(sphere_z / n) < 4.0 * std::sqrt(1.0 / 3.0 / n));
  CHECK(std::fabs(sphere_z2 / n - 1.0 / 3.0) < 4.0 * std::sqrt(4.0 / 45.0 / n));
  CHECK(std::fabs(hemi_z / n - 2.0 / 3.0) < 4.0 * std::sqrt(1.0 / 18.0 / n));
  CHECK(tessera::concentric_disk(0.5, 0.5) == tessera::Vec2(0.0));
}

TEST_CASE("random streams are pure functions of (seed, frame, pixel, sample)", "[sampling]") {
  auto first = [](std::uint64_t s, std::uint64_t f, std::uint64_t p, std::uint64_t i) {
    Rng r(s, f, p, i);
    std::vector<std::uint64_t> v;
    for (int k = 0; k < 8; ++k) v.push_back(r.next_u64());
    return v;
  };
  CHECK(first(1, 2, 3, 4) == first(1, 2, 3, 4));
  std::set<std::vector<std::uint64_t>> distinct = {first(1, 2, 3, 4), first(2, 2, 3, 4), first(1, 3, 3, 4),
                                                   first(1, 2, 4, 4), first(1, 2, 3, 5), first(0, 0, 0, 0)};
  CHECK(distinct.size() == 6);
  Rng r(5, 6, 7, 8);
  double sum = 0.0;
  bool in_range = true;
  for (int i = 0; i < 100000; ++i) {
    const double u = r.uniform();
    in_range = in_range && u >= 0.0 && u < 1.0;
    sum += u;
  }
  CHECK(in_range);
  // Mean of 1e5 uniforms: sd 1 / sqrt(12e5); 4 sigma
  CHECK(std::fabs(sum / 100000 - 0.5) < 4.0 / std::sqrt(12.0e5));
}
