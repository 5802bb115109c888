#pragma once
/// The accuracy suite's reference geometry, independent of tessera::Camera and of the
/// renderer's samplers: a thin-lens reference camera, ray/box geometry, low-discrepancy points
/// and small scene builders. Part of accuracy_support.h (which includes it); test code only.
#include "accuracy_support.h"

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

namespace tessera_acc {  // its using-declarations (Color, Vec3, ...) are accuracy_support.h's

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
  for (int k = 0; k < n; ++k) s += f(cam.ray(px + seq.at(k, 0), py + seq.at(k, 1), seq.at(k, 2), seq.at(k, 3)));
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
inline PixelTest absorbing_box_test(const FieldView& view, const tessera::SceneDesc& s, const Vec3& lo, const Vec3& hi,
                                    double sigma, int m = 64, tessera::RenderStats* stats = nullptr) {
  const std::vector<double> T = expected_image(s, m, [&](const Ray& r) { return std::exp(-sigma * chord(r, lo, hi)); });
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
