#pragma once
/// Shared tools of the accuracy suite (tests/accuracy) and the accuracy benchmark
/// (bench/accuracy): statistics (per-pixel z and chi-square tests with stated significance),
/// an independent reference camera written from docs/physics.md section 8, ray/box geometry,
/// low-discrepancy points and small scene builders (the scenes that the benchmark repeats:
/// reference_scenes.h). Header-only; test code only.
///
/// Statistical conventions (docs/accuracy.md): a per-pixel comparison passes when both
///  - the sum over pixels of z^2 is below the chi-square critical value at upper-tail
///    probability alpha, with one degree of freedom per pixel of non-zero variance (a pixel of
///    zero variance, e.g. one that sees only the background, must match exactly), and
///  - the largest |z| is below the two-sided Bonferroni bound for alpha over all pixels,
/// with alpha = 1e-4 unless a test says otherwise. Seeds are fixed, so every outcome is
/// reproducible; alpha is the probability that a correct renderer fails with a fresh seed.
#include <tessera/film.h>
#include <tessera/math.h>
#include <tessera/render.h>
#include <tessera/scene.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace tessera_acc {

using tessera::Color;
using tessera::FieldView;
using tessera::Ray;
using tessera::Vec3;
using tessera::kPi;

// ------------------------------------------------------------------------------------------
// Distributions
// ------------------------------------------------------------------------------------------

/// z with P(Z > z) = p for a standard normal Z (bisection on erfc; |error| < 1e-12).
inline double normal_upper_quantile(double p) {
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(mid / std::sqrt(2.0)) > p) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

/// Upper critical value of chi-square with k degrees of freedom at upper-tail probability
/// alpha (Wilson-Hilferty; relative error < 1% for k >= 5, conservative enough below).
inline double chi2_critical(int k, double alpha) {
  const double z = normal_upper_quantile(alpha);
  const double a = 2.0 / (9.0 * k);
  const double c = 1.0 - a + z * std::sqrt(a);
  return k * c * c * c;
}

/// Pearson chi-square of observed counts against expected probabilities. Bins with an
/// expected count under 5 are merged into the following bin (a leftover tail into the last
/// bin kept). *dof = bins kept - 1.
inline double chi_square(const std::vector<double>& observed, const std::vector<double>& prob, double total, int* dof) {
  std::vector<double> o, e;
  double oa = 0.0, ea = 0.0;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    oa += observed[i];
    ea += prob[i] * total;
    if (ea >= 5.0) {
      o.push_back(oa);
      e.push_back(ea);
      oa = ea = 0.0;
    }
  }
  if (oa > 0.0 || ea > 0.0) {
    if (e.empty()) {
      o.push_back(oa);
      e.push_back(ea);
    } else {
      o.back() += oa;
      e.back() += ea;
    }
  }
  double chi2 = 0.0;
  for (std::size_t i = 0; i < o.size(); ++i)
    chi2 += e[i] > 0.0 ? (o[i] - e[i]) * (o[i] - e[i]) / e[i] : (o[i] > 0.0 ? 1e300 : 0.0);
  *dof = static_cast<int>(o.size()) - 1;
  return chi2;
}

/// Least-squares slope of y against x (an order of convergence, on log-log axes).
inline double least_squares_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= x.size();
  my /= y.size();
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  return sxy / sxx;
}

// ------------------------------------------------------------------------------------------
// Per-pixel comparisons
// ------------------------------------------------------------------------------------------

/// Luminance mean of each pixel and the variance of that mean (sample variance / n).
struct PixelMoments {
  std::vector<double> mean, var_mean;
  std::vector<std::uint64_t> n;
};

inline PixelMoments pixel_moments(const tessera::Film& film) {
  PixelMoments m;
  for (const tessera::PixelSums& p : film.pixels()) {
    const double n = static_cast<double>(p.n);
    const double mu = n > 0 ? p.lum / n : 0.0;
    double v = 0.0;
    if (p.n > 1) v = std::max(0.0, (p.lum2 - p.lum * mu) / (n - 1.0)) / n;
    m.mean.push_back(mu);
    m.var_mean.push_back(v);
    m.n.push_back(p.n);
  }
  return m;
}

/// Mean squared error of the pixel means `m` against an independent reference `ref`, less the
/// reference's own noise `ref_var` (the mean over pixels of ref.var_mean; the cross term has
/// mean zero as the films are independent). Not clamped: <= 0 once the reference's noise
/// dominates.
inline double mse_vs_reference(const PixelMoments& m, const PixelMoments& ref, double ref_var) {
  double mse = 0.0;
  for (std::size_t i = 0; i < m.mean.size(); ++i) mse += (m.mean[i] - ref.mean[i]) * (m.mean[i] - ref.mean[i]);
  return mse / m.mean.size() - ref_var;
}

/// Result of a per-pixel test; ok() applies the rule of the file comment.
struct PixelTest {
  int pixels = 0;
  int dof = 0;  ///< pixels with a non-zero variance (the others must match exactly)
  double alpha = 1e-4;
  double chi2 = 0.0, chi2_crit = 0.0;
  double max_abs_z = 0.0, z_crit = 0.0;
  int worst = -1;             ///< pixel index of max |z|
  double mean_diff = 0.0;     ///< image mean of (measured - expected)
  double mean_diff_se = 0.0;  ///< its standard error
  double mean_expected = 0.0;
  /// Binomial tests only (compare_binomial): pixels where one outcome is rare are pooled, per
  /// rare outcome, into a Poisson test of the total count: observed, expected and two-sided
  /// p-value; [0] rare events (value), [1] rare non-events (0).
  int rare_pixels = 0;
  double rare_observed[2] = {0, 0}, rare_expected[2] = {0, 0}, rare_p[2] = {1, 1};
  bool ok() const { return chi2 < chi2_crit && max_abs_z < z_crit && rare_p[0] >= alpha && rare_p[1] >= alpha; }
  double mean_z() const {
    return mean_diff_se > 0.0 ? std::fabs(mean_diff) / mean_diff_se : (mean_diff == 0.0 ? 0.0 : INFINITY);
  }
  std::string describe() const {
    std::ostringstream s;
    s << pixels << " pixels: chi2 " << chi2 << " on " << dof << " dof (critical " << chi2_crit << "), max |z| "
      << max_abs_z << " at pixel " << worst << " (critical " << z_crit << "), image mean diff " << mean_diff << " +- "
      << mean_diff_se << " (expected mean " << mean_expected << ")";
    if (rare_pixels > 0)
      s << "; " << rare_pixels << " pixels pooled: rare events " << rare_observed[0] << " (expected "
        << rare_expected[0] << ", p " << rare_p[0] << "), rare non-events " << rare_observed[1] << " (expected "
        << rare_expected[1] << ", p " << rare_p[1] << ")";
    return s.str();
  }
};

/// z-scores (a - b) / sqrt(va + vb) per pixel, combined as described above. A pixel with zero
/// variance contributes z = 0 if a == b up to 1e-12 relative, else z = infinity.
inline PixelTest combine_z(const std::vector<double>& a, const std::vector<double>& va, const std::vector<double>& b,
                           const std::vector<double>& vb, double alpha = 1e-4) {
  PixelTest t;
  t.alpha = alpha;
  t.pixels = static_cast<int>(a.size());
  double var_sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double v = va[i] + vb[i];
    const double d = a[i] - b[i];
    double z;
    if (v > 0.0) {
      z = d / std::sqrt(v);
      ++t.dof;
    } else {
      z = std::fabs(d) <= 1e-12 * std::max(1.0, std::fabs(b[i])) ? 0.0 : INFINITY;
    }
    t.chi2 += z * z;
    if (t.worst < 0 || !(std::fabs(z) <= t.max_abs_z)) {
      t.max_abs_z = std::fabs(z);
      t.worst = static_cast<int>(i);
    }
    t.mean_diff += d;
    t.mean_expected += b[i];
    var_sum += v;
  }
  const double n = static_cast<double>(a.size());
  t.mean_diff /= n;
  t.mean_expected /= n;
  t.mean_diff_se = std::sqrt(var_sum) / n;
  t.chi2_crit = chi2_critical(std::max(1, t.dof), alpha);
  t.z_crit = normal_upper_quantile(alpha / (2.0 * n));
  return t;
}

/// Film luminance against expected pixel means. `sample_var` (optional) is the exact
/// per-sample variance of each pixel (e.g. Bernoulli T(1-T)); without it the film's own
/// sample variance is used.
inline PixelTest compare_to_expected(const tessera::Film& film, const std::vector<double>& expected,
                                     const std::vector<double>* sample_var = nullptr, double alpha = 1e-4) {
  const PixelMoments m = pixel_moments(film);
  std::vector<double> v = m.var_mean;
  if (sample_var)
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = (*sample_var)[i] / static_cast<double>(m.n[i]);
  return combine_z(m.mean, v, expected, std::vector<double>(expected.size(), 0.0), alpha);
}

/// Two-sided p-value of observing c from a Poisson distribution of mean mu (exact sums of the
/// pmf in log space; normal approximation beyond mu = 1e4).
inline double poisson_two_sided(double c, double mu) {
  if (mu <= 0.0) return c == 0.0 ? 1.0 : 0.0;
  if (mu > 1e4) return std::erfc(std::fabs(c - mu) / std::sqrt(2.0 * mu));
  double lower = 0.0, upper = 0.0;  // P(X <= c), P(X >= c)
  const int ci = static_cast<int>(std::lround(c));
  const int top = std::max(ci, static_cast<int>(mu + 40.0 * std::sqrt(mu) + 40.0));
  for (int j = 0; j <= top; ++j) {
    const double pmf = std::exp(j * std::log(mu) - mu - std::lgamma(j + 1.0));
    if (j <= ci) lower += pmf;
    if (j >= ci) upper += pmf;
  }
  return std::min(1.0, 2.0 * std::min(lower, upper));
}

/// A film whose samples are `value` with probability P[i] in pixel i and 0 otherwise (e.g.
/// escape / no escape through an absorber): the per-pixel counts are binomial. Pixels with
/// n P >= 10 and n (1 - P) >= 10 get z = (mean - value P) / (value sqrt(P (1 - P) / n)) and
/// the chi-square / Bonferroni rule; pixels where an outcome is rarer are pooled, per rare
/// outcome, into one Poisson test of its total count (exact two-sided p-value >= alpha).
/// P = 0 or 1 must be matched exactly.
inline PixelTest compare_binomial(const tessera::Film& film, const std::vector<double>& P, double value,
                                  double alpha = 1e-4) {
  std::vector<double> a, va, b;
  double rare_obs[2] = {0, 0}, rare_exp[2] = {0, 0};
  int rare = 0;
  bool exact_ok = true;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const tessera::PixelSums& p = film.pixels()[i];
    const double n = static_cast<double>(p.n), k = std::round(p.r / value);
    const double np = n * P[i], nq = n * (1.0 - P[i]);
    if (P[i] <= 0.0 || P[i] >= 1.0) {
      exact_ok = exact_ok && k == (P[i] >= 1.0 ? n : 0.0);
    } else if (np >= 10.0 && nq >= 10.0) {
      a.push_back(p.r / n);
      va.push_back(value * value * P[i] * (1.0 - P[i]) / n);
      b.push_back(value * P[i]);
    } else {
      ++rare;
      if (np < nq) rare_obs[0] += k, rare_exp[0] += np;
      else rare_obs[1] += n - k, rare_exp[1] += nq;
    }
  }
  PixelTest t = a.empty() ? PixelTest{} : combine_z(a, va, b, std::vector<double>(b.size(), 0.0), alpha);
  t.alpha = alpha;
  if (a.empty()) {
    t.chi2_crit = INFINITY;
    t.z_crit = INFINITY;
  }
  t.rare_pixels = rare;
  for (int g = 0; g < 2; ++g) {
    t.rare_observed[g] = rare_obs[g];
    t.rare_expected[g] = rare_exp[g];
    t.rare_p[g] = poisson_two_sided(rare_obs[g], rare_exp[g]);
  }
  if (!exact_ok) t.max_abs_z = INFINITY;
  return t;
}

/// Two independent films of the same scene: per-pixel difference against 0.
inline PixelTest compare_films(const tessera::Film& a, const tessera::Film& b, double alpha = 1e-4) {
  const PixelMoments ma = pixel_moments(a), mb = pixel_moments(b);
  return combine_z(ma.mean, ma.var_mean, mb.mean, mb.var_mean, alpha);
}

/// Mean of the pixel luminance means and its standard error.
struct ImageMean {
  double mean = 0.0, se = 0.0;
  double z(double expected) const {
    return std::fabs(mean - expected) / std::max(se, 1e-12 * std::max(1.0, std::fabs(expected)));
  }
};
inline ImageMean image_mean(const tessera::Film& film) {
  const PixelMoments m = pixel_moments(film);
  ImageMean r;
  double v = 0.0;
  for (std::size_t i = 0; i < m.mean.size(); ++i) {
    r.mean += m.mean[i];
    v += m.var_mean[i];
  }
  const double n = static_cast<double>(m.mean.size());
  r.mean /= n;
  r.se = std::sqrt(v) / n;
  return r;
}

inline bool bit_identical(const tessera::Film& a, const tessera::Film& b) {
  if (a.pixels().size() != b.pixels().size()) return false;
  for (std::size_t i = 0; i < a.pixels().size(); ++i) {
    const tessera::PixelSums &p = a.pixels()[i], &q = b.pixels()[i];
    if (p.r != q.r || p.g != q.g || p.b != q.b || p.a != q.a || p.lum != q.lum || p.lum2 != q.lum2 || p.n != q.n ||
        p.drawn != q.drawn)
      return false;
  }
  return true;
}

inline bool all_finite(const tessera::Film& film) {
  for (const tessera::PixelSums& p : film.pixels())
    if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b) || !std::isfinite(p.a) ||
        !std::isfinite(p.lum2))
      return false;
  const tessera::Image img = film.resolve();
  for (float v : img.rgba)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace tessera_acc

#include "reference_geometry.h"
