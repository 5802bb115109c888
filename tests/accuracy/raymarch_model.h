#pragma once
/// Deterministic models for reference (e), the ray-march bias (docs/accuracy.md, "Ray-march
/// bias"), shared by tests/accuracy and bench/accuracy.
///
/// A purely absorbing medium with sigma_t(x) = s * v(x), v the trilinear interpolant of a
/// float vertex array (with opacity = identity and v inside [lo, hi], so no clamping).
///  - exact_transmittance: exp(-integral of sigma_t) along a ray. The ray is cut where it
///    crosses voxel planes; inside a voxel v is a cubic in t, which 3-point Gauss-Legendre
///    integrates exactly.
///  - raymarch_transmittance: the expectation over the jitter xi in [0,1) of
///    exp(-S(xi)), S(xi) = h * sum over t_i = t0 + (xi + i) h < t1 of sigma_t(t_i): the
///    probability that docs/physics.md's fixed-step march (threshold -ln(1 - u), first sample
///    at t0 + xi h) lets the ray escape. With (t1 - t0) / h = K + f, S has K + 1 terms for
///    xi < f and K terms after; each part is integrated by an m-point midpoint rule.
#include "accuracy_support.h"

#include <vector>

namespace tessera_acc {

struct TrilinearField {
  std::vector<float> v;  ///< C order, i fastest
  int n[3];
  Vec3 origin, spacing;
  double scale;  ///< sigma_t = scale * value

  double value(const Vec3& x) const {
    double f[3];
    int i0[3];
    for (int a = 0; a < 3; ++a) {
      const double p = std::clamp((x[a] - origin[a]) / spacing[a], 0.0, n[a] - 1.0);
      int i = static_cast<int>(std::floor(p));
      i = std::min(i, n[a] - 2);
      i0[a] = i;
      f[a] = p - i;
    }
    auto at = [&](int di, int dj, int dk) {
      return static_cast<double>(v[(static_cast<std::size_t>(i0[2] + dk) * n[1] + (i0[1] + dj)) * n[0] + (i0[0] + di)]);
    };
    double r = 0.0;
    for (int c = 0; c < 8; ++c) {
      const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
      r += (dx ? f[0] : 1.0 - f[0]) * (dy ? f[1] : 1.0 - f[1]) * (dz ? f[2] : 1.0 - f[2]) * at(dx, dy, dz);
    }
    return r;
  }
  double sigma(const Vec3& x) const { return scale * value(x); }
  Vec3 lo() const { return origin; }
  Vec3 hi() const { return origin + Vec3(n[0] - 1, n[1] - 1, n[2] - 1) * spacing; }
};

/// exp(-optical depth) through the box along r.
inline double exact_transmittance(const TrilinearField& m, const Ray& r) {
  double t0, t1;
  if (!box_interval(r, m.lo(), m.hi(), &t0, &t1)) return 1.0;
  std::vector<double> cuts{t0, t1};
  for (int a = 0; a < 3; ++a) {
    if (r.d[a] == 0.0) continue;
    for (int k = 1; k < m.n[a] - 1; ++k) {
      const double t = (m.origin[a] + k * m.spacing[a] - r.o[a]) / r.d[a];
      if (t > t0 && t < t1) cuts.push_back(t);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  static const double x3[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w3[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  double od = 0.0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double c = 0.5 * (cuts[i] + cuts[i + 1]), h = 0.5 * (cuts[i + 1] - cuts[i]);
    for (int q = 0; q < 3; ++q) od += h * w3[q] * m.sigma(r.o + (c + h * x3[q]) * r.d);
  }
  return std::exp(-od);
}

/// Expected escape probability of the fixed-step march with step h (world units).
inline double raymarch_transmittance(const TrilinearField& m, const Ray& r, double h, int mpts) {
  double t0, t1;
  if (!box_interval(r, m.lo(), m.hi(), &t0, &t1)) return 1.0;
  const double q = (t1 - t0) / h;
  const double K = std::floor(q), f = q - K;
  auto S = [&](double xi) {
    double s = 0.0;
    for (double t = t0 + xi * h; t < t1; t += h) s += m.sigma(r.o + t * r.d);
    return s * h;
  };
  double e = 0.0;
  for (int k = 0; k < mpts; ++k) {
    e += f * std::exp(-S(f * (k + 0.5) / mpts));                      // xi in [0, f): K + 1 terms
    e += (1.0 - f) * std::exp(-S(f + (1.0 - f) * (k + 0.5) / mpts));  // xi in [f, 1): K terms
  }
  return e / mpts;
}

/// The smooth field of the ray-march tests: values in [0.25, 0.85], non-zero on the faces
/// (so the march's end effects, the leading error term, are present), n^3 vertices on
/// [0, 1]^3.
inline TrilinearField raymarch_field(int n, double scale) {
  TrilinearField m;
  m.n[0] = m.n[1] = m.n[2] = n;
  m.origin = Vec3(0.0);
  m.spacing = Vec3(1.0 / (n - 1));
  m.scale = scale;
  m.v.resize(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = i * m.spacing.x, y = j * m.spacing.y, z = k * m.spacing.z;
        m.v[(static_cast<std::size_t>(k) * n + j) * n + i] = static_cast<float>(
            0.55 + 0.2 * std::sin(3.1 * x + 0.4) * std::cos(2.3 * y - 0.3) + 0.1 * std::cos(4.0 * z + 1.0));
      }
  return m;
}

}  // namespace tessera_acc
