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
inline double chi_square(const std::vector<double>& observed, const std::vector<double>& prob,
                         double total, int* dof) {
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
  int dof = 0;                   ///< pixels with a non-zero variance (the others must match exactly)
  double alpha = 1e-4;
  double chi2 = 0.0, chi2_crit = 0.0;
  double max_abs_z = 0.0, z_crit = 0.0;
  int worst = -1;                ///< pixel index of max |z|
  double mean_diff = 0.0;        ///< image mean of (measured - expected)
  double mean_diff_se = 0.0;     ///< its standard error
  double mean_expected = 0.0;
  /// Binomial tests only (compare_binomial): pixels where one outcome is rare are pooled, per
  /// rare outcome, into a Poisson test of the total count: observed, expected and two-sided
  /// p-value; [0] rare events (value), [1] rare non-events (0).
  int rare_pixels = 0;
  double rare_observed[2] = {0, 0}, rare_expected[2] = {0, 0}, rare_p[2] = {1, 1};
  bool ok() const {
    return chi2 < chi2_crit && max_abs_z < z_crit && rare_p[0] >= alpha && rare_p[1] >= alpha;
  }
  double mean_z() const { return mean_diff_se > 0.0 ? std::fabs(mean_diff) / mean_diff_se : (mean_diff == 0.0 ? 0.0 : INFINITY); }
  std::string describe() const {
    std::ostringstream s;
    s << pixels << " pixels: chi2 " << chi2 << " on " << dof << " dof (critical " << chi2_crit << "), max |z| "
      << max_abs_z << " at pixel " << worst << " (critical " << z_crit << "), image mean diff "
      << mean_diff << " +- " << mean_diff_se << " (expected mean " << mean_expected << ")";
    if (rare_pixels > 0)
      s << "; " << rare_pixels << " pixels pooled: rare events " << rare_observed[0] << " (expected "
        << rare_expected[0] << ", p " << rare_p[0] << "), rare non-events " << rare_observed[1]
        << " (expected " << rare_expected[1] << ", p " << rare_p[1] << ")";
    return s.str();
  }
};

/// z-scores (a - b) / sqrt(va + vb) per pixel, combined as described above. A pixel with zero
/// variance contributes z = 0 if a == b up to 1e-12 relative, else z = infinity.
inline PixelTest combine_z(const std::vector<double>& a, const std::vector<double>& va,
                           const std::vector<double>& b, const std::vector<double>& vb,
                           double alpha = 1e-4) {
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
                                     const std::vector<double>* sample_var = nullptr,
                                     double alpha = 1e-4) {
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
    if (p.r != q.r || p.g != q.g || p.b != q.b || p.a != q.a || p.lum != q.lum ||
        p.lum2 != q.lum2 || p.n != q.n || p.drawn != q.drawn)
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

// ------------------------------------------------------------------------------------------
// Reference geometry, independent of tessera::Camera
// ------------------------------------------------------------------------------------------

/// Pinhole / thin-lens camera written from docs/physics.md section 8. The lens point is
/// parametrised in polar form (r = aperture sqrt(a), phi = 2 pi b), a different map from the
/// renderer's concentric one, with the same (uniform) distribution on the lens disk.
struct RefCamera {
  Vec3 pos, fwd, right, up;
  double tan_half, aspect, aperture, focus;
  int w, h;
  RefCamera(const tessera::CameraDesc& c, int width, int height) {
    pos = c.position;
    fwd = glm::normalize(c.look_at - c.position);
    right = glm::normalize(glm::cross(fwd, c.up));
    up = glm::cross(right, fwd);
    tan_half = std::tan(0.5 * c.fov_deg * kPi / 180.0);
    aspect = static_cast<double>(width) / height;
    aperture = c.aperture;
    focus = c.focus_distance > 0.0 ? c.focus_distance : glm::length(c.look_at - c.position);
    w = width;
    h = height;
  }
  /// Ray through image point (px, py) (pixel units, py = 0 top) and lens point (a, b).
  Ray ray(double px, double py, double a = 0.0, double b = 0.0) const {
    const double sx = (2.0 * px / w - 1.0) * tan_half * aspect;
    const double sy = (1.0 - 2.0 * py / h) * tan_half;
    const Vec3 d = glm::normalize(fwd + sx * right + sy * up);
    if (aperture <= 0.0) return Ray{pos, d};
    const Vec3 focal = pos + d * (focus / glm::dot(d, fwd));
    const double r = aperture * std::sqrt(a), phi = 2.0 * kPi * b;
    const Vec3 o = pos + r * std::cos(phi) * right + r * std::sin(phi) * up;
    return Ray{o, glm::normalize(focal - o)};
  }
};

/// Ray / axis-aligned box, clipped to t >= 0: the interval [*t0, *t1] inside the box.
inline bool box_interval(const Ray& r, const Vec3& lo, const Vec3& hi, double* t0, double* t1) {
  double a = 0.0, b = INFINITY;
  for (int ax = 0; ax < 3; ++ax) {
    if (r.d[ax] == 0.0) {
      if (r.o[ax] < lo[ax] || r.o[ax] > hi[ax]) return false;
      continue;
    }
    double ta = (lo[ax] - r.o[ax]) / r.d[ax], tb = (hi[ax] - r.o[ax]) / r.d[ax];
    if (ta > tb) std::swap(ta, tb);
    a = std::max(a, ta);
    b = std::min(b, tb);
  }
  *t0 = a;
  *t1 = b;
  return a < b;
}

inline double chord(const Ray& r, const Vec3& lo, const Vec3& hi) {
  double t0, t1;
  return box_interval(r, lo, hi, &t0, &t1) ? t1 - t0 : 0.0;
}

/// Points of the R_d low-discrepancy sequence (Roberts 2018) in [0,1)^d, d <= 4.
struct RSequence {
  double alpha[4];
  int d;
  explicit RSequence(int dim) : d(dim) {
    double phi = 2.0;  // root of x^(d+1) = x + 1
    for (int i = 0; i < 64; ++i) phi = std::pow(1.0 + phi, 1.0 / (dim + 1));
    double p = 1.0;
    for (int i = 0; i < 4; ++i) {
      p /= phi;
      alpha[i] = p;
    }
  }
  double at(std::uint64_t n, int i) const {
    const double v = 0.5 + alpha[i] * static_cast<double>(n);
    return v - std::floor(v);
  }
};

/// Pixel average of f(ray) for a pinhole camera: m x m midpoint rule over the pixel.
template <class F>
double pixel_average_pinhole(const RefCamera& cam, int px, int py, int m, F&& f) {
  double s = 0.0;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) s += f(cam.ray(px + (i + 0.5) / m, py + (j + 0.5) / m));
  return s / (m * m);
}

/// Pixel average of f(ray) over the pixel and the lens: n points of the R_4 sequence.
template <class F>
double pixel_average_lens(const RefCamera& cam, int px, int py, int n, F&& f) {
  static const RSequence seq(4);
  double s = 0.0;
  for (int k = 0; k < n; ++k)
    s += f(cam.ray(px + seq.at(k, 0), py + seq.at(k, 1), seq.at(k, 2), seq.at(k, 3)));
  return s / n;
}

/// Per-pixel expected values of f over a scene's image (pinhole: m x m per pixel; thin
/// lens: m*m*lens_factor R_4 points per pixel).
template <class F>
std::vector<double> expected_image(const tessera::SceneDesc& s, int m, F&& f, int lens_points = 1 << 14) {
  const RefCamera cam(s.camera, s.image.width, s.image.height);
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(s.image.width) * s.image.height);
  for (int y = 0; y < s.image.height; ++y)
    for (int x = 0; x < s.image.width; ++x)
      out.push_back(s.camera.aperture > 0.0 ? pixel_average_lens(cam, x, y, lens_points, f)
                                            : pixel_average_pinhole(cam, x, y, m, f));
  return out;
}

// ------------------------------------------------------------------------------------------
// Scenes and rendering
// ------------------------------------------------------------------------------------------

/// Constant float field of nx x ny x nz vertices.
inline std::vector<float> constant_field(int nx, int ny, int nz, float v) {
  return std::vector<float>(static_cast<std::size_t>(nx) * ny * nz, v);
}

/// A smooth heterogeneous field in [0.05, 1] (blobs on a base), C order, i fastest.
inline std::vector<float> cloud_field(int nx, int ny, int nz) {
  std::vector<float> f(static_cast<std::size_t>(nx) * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x = static_cast<double>(i) / (nx - 1), y = static_cast<double>(j) / (ny - 1),
                     z = static_cast<double>(k) / (nz - 1);
        const double b1 = std::exp(-((x - 0.35) * (x - 0.35) + (y - 0.4) * (y - 0.4) + (z - 0.5) * (z - 0.5)) / 0.03);
        const double b2 = std::exp(-((x - 0.7) * (x - 0.7) + (y - 0.65) * (y - 0.65) + (z - 0.35) * (z - 0.35)) / 0.02);
        const double v = 0.05 + 0.8 * b1 + 0.6 * b2 + 0.1 * std::sin(9.0 * x + 4.0 * y) * std::cos(7.0 * z);
        f[(static_cast<std::size_t>(k) * ny + j) * nx + i] = static_cast<float>(std::clamp(v, 0.0, 1.0));
      }
  return f;
}

/// Render a scene into a fresh film.
inline tessera::Film render(const FieldView& field, const tessera::SceneDesc& s,
                            tessera::RenderStats* stats = nullptr) {
  const tessera::PreparedScene ps = tessera::prepare(field, s);
  tessera::Film film(s.image.width, s.image.height);
  tessera::RenderStats st;
  tessera::render(ps, film, st);
  if (stats) *stats = st;
  return film;
}

/// A unit box [0,1]^3 scene: constant opacity 1 (sigma_t = density_scale), phase shading,
/// single scattering, black background, no lights; callers set the rest.
inline tessera::SceneDesc unit_box_scene(double sigma, double albedo) {
  tessera::SceneDesc s;
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = sigma;
  s.tf.opacity = tessera::ScalarTF::constant(1.0);
  s.tf.diffuse = tessera::ColorTF::constant(Color(albedo));
  s.integrator.shading = tessera::Shading::Phase;
  s.integrator.scattering = tessera::Scattering::Single;
  s.background.color = Color(0.0);
  s.options.seed = 1;
  return s;
}

/// Reference (a) as a reusable check: `s` renders an absorbing box [lo, hi] of extinction
/// sigma (albedo 0) in front of a constant background of radiance 1 and nothing else, so each
/// pixel's escape count is Binomial(n, T_pix), T_pix = E[exp(-sigma chord)] over the pixel
/// (and lens). Returns the per-pixel test of the film against T_pix.
inline PixelTest absorbing_box_test(const FieldView& view, const tessera::SceneDesc& s, const Vec3& lo,
                                    const Vec3& hi, double sigma, int m = 64,
                                    tessera::RenderStats* stats = nullptr) {
  const std::vector<double> T = expected_image(s, m, [&](const Ray& r) {
    return std::exp(-sigma * chord(r, lo, hi));
  });
  const tessera::Film film = render(view, s, stats);
  if (!all_finite(film)) {
    PixelTest bad;
    bad.chi2 = INFINITY;
    return bad;
  }
  return compare_binomial(film, T, 1.0);
}

/// Henyey-Greenstein, written from docs/physics.md "Scattering models" for the references.
inline double hg(double cos_theta, double g) {
  const double d = 1.0 + g * g - 2.0 * g * cos_theta;
  return (1.0 - g * g) / (4.0 * kPi * d * std::sqrt(d));
}

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n; n <= 256).
struct GaussLegendre {
  std::vector<double> x, w;
  explicit GaussLegendre(int n) : x(n), w(n) {
    for (int i = 0; i < n; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::fabs(dz) < 1e-16) break;
      }
      x[i] = z;
      w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
  }
  /// Integral of f over [a, b].
  template <class F>
  double integrate(double a, double b, F&& f) const {
    const double c = 0.5 * (a + b), h = 0.5 * (b - a);
    double s = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) s += w[i] * f(c + h * x[i]);
    return s * h;
  }
};

}  // namespace tessera_acc
