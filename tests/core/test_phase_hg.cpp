// Tests for the Henyey-Greenstein phase function: it integrates to 1, sampled directions follow
// it (chi-square on cos theta and on the azimuth), the returned pdf is the phase value, the mean
// cosine is g, and g > 0 scatters forward along the travel direction.
//
// Statistics: chi-square tests at significance 1e-4 (Wilson-Hilferty critical value), mean
// cosine within 4 standard errors (two-sided, 6.3e-5). Fixed seeds.
#include <catch2/catch.hpp>

#include "kernel/phase_hg.h"
#include "sampling/rng.h"
#include "sampling/warp.h"
#include "test_support.h"

#include <cmath>
#include <vector>

using tessera::Vec3;

namespace {

/// 2 pi * integral of hg_eval over cos theta in [a, b], composite Simpson.
double hg_mass(double a, double b, double g) {
  const int n = 400;
  const double h = (b - a) / n;
  double s = tessera::hg_eval(a, g) + tessera::hg_eval(b, g);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * tessera::hg_eval(a + i * h, g);
  return 2.0 * tessera::kPi * s * h / 3.0;
}

}  // namespace

TEST_CASE("HG phase function integrates to 1 over the sphere", "[phase_hg]") {
  for (const double g : {-0.95, -0.7, -0.3, 0.0, 0.2, 0.7, 0.95}) {
    double total = 0.0;
    for (int i = 0; i < 100; ++i) total += hg_mass(-1.0 + i * 0.02, -1.0 + (i + 1) * 0.02, g);
    INFO("g " << g);
    CHECK(total == Approx(1.0).epsilon(1e-6));
  }
  CHECK(tessera::hg_eval(0.3, 0.0) == Approx(tessera::kInv4Pi).epsilon(1e-15));
}

TEST_CASE("HG sampling matches hg_eval: histogram of cos theta and azimuth, pdf, mean cosine", "[phase_hg]") {
  constexpr int kSamples = 200000, kBins = 40, kPhiBins = 16;
  tessera::Rng rng(31337, 0, 0, 0);
  for (const double g : {-0.7, -0.2, 0.0, 0.0005, 0.5, 0.9}) {
    // A random travel direction, and the exact poles now and then
    const Vec3 d_in = g == 0.5 ? Vec3(0.0, 0.0, -1.0) : tessera::uniform_sphere(rng.uniform(), rng.uniform());
    const tessera::Frame frame(d_in);
    std::vector<double> hist(kBins, 0.0), phi_hist(kPhiBins, 0.0);
    double sum_cos = 0.0, sum_cos2 = 0.0, worst_pdf = 0.0, worst_norm = 0.0;
    for (int i = 0; i < kSamples; ++i) {
      Vec3 d_out;
      const double pdf = tessera::hg_sample(d_in, g, rng.uniform(), rng.uniform(), &d_out);
      const double c = glm::dot(d_in, d_out);
      worst_norm = std::fmax(worst_norm, std::fabs(glm::length(d_out) - 1.0));
      worst_pdf = std::fmax(worst_pdf, std::fabs(pdf / tessera::hg_eval(c, g) - 1.0));
      sum_cos += c;
      sum_cos2 += c * c;
      hist[std::min(kBins - 1, static_cast<int>((c + 1.0) * 0.5 * kBins))] += 1.0;
      const Vec3 l = frame.to_local(d_out);
      double phi = std::atan2(l.y, l.x);
      if (phi < 0.0) phi += 2.0 * tessera::kPi;
      phi_hist[std::min(kPhiBins - 1, static_cast<int>(phi / (2.0 * tessera::kPi) * kPhiBins))] += 1.0;
    }
    std::vector<double> prob(kBins);
    for (int b = 0; b < kBins; ++b) prob[b] = hg_mass(-1.0 + 2.0 * b / kBins, -1.0 + 2.0 * (b + 1) / kBins, g);
    int dof = 0;
    const double chi2 = tessera_test::chi_square(hist, prob, kSamples, &dof);
    const std::vector<double> uniform(kPhiBins, 1.0 / kPhiBins);
    int dof_phi = 0;
    const double chi2_phi = tessera_test::chi_square(phi_hist, uniform, kSamples, &dof_phi);

    const double mean = sum_cos / kSamples;
    const double se = std::sqrt(std::fmax(0.0, sum_cos2 / kSamples - mean * mean) / kSamples);
    INFO("g " << g << ": chi2 " << chi2 << " dof " << dof << ", azimuth chi2 " << chi2_phi << " dof " << dof_phi
              << ", mean cos " << mean << " +- " << se);
    CHECK(chi2 < tessera_test::chi2_critical(dof, tessera_test::kZ1e4));
    CHECK(chi2_phi < tessera_test::chi2_critical(dof_phi, tessera_test::kZ1e4));
    CHECK(std::fabs(mean - g) < 4.0 * se);
    CHECK(worst_pdf < 1e-9);
    CHECK(worst_norm < 1e-12);
  }
}

TEST_CASE("HG with g > 0 scatters forward along the direction of travel", "[phase_hg]") {
  // hg_eval takes cos(angle between travel-in and travel-out): forward is cos = 1
  CHECK(tessera::hg_eval(1.0, 0.8) > tessera::hg_eval(-1.0, 0.8));
  CHECK(tessera::hg_eval(1.0, -0.8) < tessera::hg_eval(-1.0, -0.8));
  Vec3 out;
  tessera::hg_sample(Vec3(1.0, 0.0, 0.0), 0.99, 0.5, 0.3, &out);
  CHECK(out.x > 0.9);
}
