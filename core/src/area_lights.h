#pragma once
/// Prepared rect and sphere lights: intersection, sampling and solid-angle pdfs.
#include <tessera/lights.h>
#include <tessera/math.h>

#include <stdexcept>
#include <string>
#include <type_traits>

namespace tessera {

struct LightSample {
  Vec3 wi;         ///< unit direction from the shading point to the light point
  double dist;     ///< distance to the light point
  Color L;         ///< radiance arriving along -wi (0 if the back side was sampled)
  double pdf;      ///< solid-angle pdf of wi under this light's strategy
};

class RectLight {
 public:
  RectLight() = default;
  explicit RectLight(const RectLightDesc& d) : m_c(d.position), m_L(d.radiance) {
    const Vec3 to = d.target - d.position;
    if (!(glm::length(to) > 0.0)) throw std::invalid_argument("rect light: target equals position");
    if (!(d.width > 0.0) || !(d.height > 0.0) || !std::isfinite(d.width) || !std::isfinite(d.height))
      throw std::invalid_argument("rect light: size " + std::to_string(d.width) + " x " +
                                  std::to_string(d.height) + " must be finite and > 0");
    m_n = glm::normalize(to);
    const Vec3 ref = std::fabs(m_n.z) > 0.999 ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
    m_u = glm::normalize(glm::cross(ref, m_n));
    m_v = glm::cross(m_n, m_u);
    m_hw = 0.5 * d.width;
    m_hh = 0.5 * d.height;
    m_area = d.width * d.height;
    m_reach = 0.5 * std::hypot(d.width, d.height);
  }

  /// Hit distance along the ray in (0, inf) of the front side, or -1.
  double intersect_front(const Ray& r) const {
    const double dn = glm::dot(r.d, m_n);
    if (!(dn < 0.0)) return -1.0;  // the front emits toward +n: a ray must travel against n
    const double t = glm::dot(m_c - r.o, m_n) / dn;
    if (!(t > 0.0)) return -1.0;
    const Vec3 p = r.o + t * r.d - m_c;
    if (std::fabs(glm::dot(p, m_u)) > m_hw || std::fabs(glm::dot(p, m_v)) > m_hh) return -1.0;
    return t;
  }
  static constexpr bool kInfinite = false;
  Color radiance() const { return m_L; }
  Color radiance(const Vec3&) const { return m_L; }  ///< the same in every direction
  /// A world box holding the rectangle: the centre +- half its diagonal on every axis.
  void bounds(Vec3* lo, Vec3* hi) const {
    *lo = m_c - Vec3(m_reach);
    *hi = m_c + Vec3(m_reach);
  }
  double pdf(const Vec3& x, const Vec3& wi, double t) const {
    const double cos_l = -glm::dot(wi, m_n);
    return cos_l > 0.0 ? t * t / (cos_l * m_area) : 0.0;
  }
  LightSample sample(const Vec3& x, double u1, double u2) const {
    const Vec3 y = m_c + (2.0 * u1 - 1.0) * m_hw * m_u + (2.0 * u2 - 1.0) * m_hh * m_v;
    const Vec3 dv = y - x;
    const double dist = glm::length(dv);
    LightSample s{Vec3(0.0), dist, Color(0.0), 0.0};
    if (!(dist > 0.0)) return s;
    s.wi = dv / dist;
    const double cos_l = -glm::dot(s.wi, m_n);
    if (cos_l <= 0.0) return s;
    s.L = m_L;
    s.pdf = dist * dist / (cos_l * m_area);
    return s;
  }

 private:
  Vec3 m_c{0.0}, m_n{0.0, 0.0, 1.0}, m_u{1.0, 0.0, 0.0}, m_v{0.0, 1.0, 0.0};
  Color m_L{0.0};
  double m_hw = 0.5, m_hh = 0.5, m_area = 1.0;
  double m_reach = 0.5;  ///< half the diagonal
};

class SphereLight {
 public:
  SphereLight() = default;
  explicit SphereLight(const SphereLightDesc& d) : m_c(d.center), m_r(d.radius), m_L(d.radiance) {
    if (!(d.radius > 0.0) || !std::isfinite(d.radius))
      throw std::invalid_argument("sphere light: radius " + std::to_string(d.radius) +
                                  " must be finite and > 0");
  }
  /// Distance to the outward-facing (front) hit, or -1. From inside there is none.
  double intersect_front(const Ray& r) const {
    const Vec3 oc = r.o - m_c;
    const double b = glm::dot(oc, r.d);
    const double c = glm::dot(oc, oc) - m_r * m_r;
    if (c <= 0.0) return -1.0;  // inside or on the sphere: only back sides ahead
    // Stable discriminant: distance from centre to the ray's line.
    const Vec3 perp = oc - b * r.d;
    const double h2 = m_r * m_r - glm::dot(perp, perp);
    if (h2 < 0.0 || b >= 0.0) return -1.0;
    const double t = -b - std::sqrt(h2);
    return t > 0.0 ? t : -1.0;
  }
  static constexpr bool kInfinite = false;
  Color radiance() const { return m_L; }
  Color radiance(const Vec3&) const { return m_L; }  ///< the same in every direction
  void bounds(Vec3* lo, Vec3* hi) const {
    *lo = m_c - Vec3(m_r);
    *hi = m_c + Vec3(m_r);
  }
  /// Uniform sampling of the visible cone.
  double pdf(const Vec3& x, const Vec3&, double) const {
    const double d2 = glm::dot(x - m_c, x - m_c);
    if (d2 <= m_r * m_r) return 0.0;
    const double sin2 = m_r * m_r / d2;
    const double one_minus_cos = sin2 / (1.0 + std::sqrt(1.0 - sin2));
    return 1.0 / (2.0 * kPi * one_minus_cos);
  }
  LightSample sample(const Vec3& x, double u1, double u2) const {
    LightSample s{Vec3(0.0), 0.0, Color(0.0), 0.0};
    const Vec3 to_c = m_c - x;
    const double d2 = glm::dot(to_c, to_c);
    if (d2 <= m_r * m_r) return s;  // inside: nothing visible from the front
    const double d = std::sqrt(d2);
    const double sin2 = m_r * m_r / d2;
    const double one_minus_cos_max = sin2 / (1.0 + std::sqrt(1.0 - sin2));
    const double one_minus_cos = u1 * one_minus_cos_max;
    const double cos_t = 1.0 - one_minus_cos;
    const double sin_t = std::sqrt(std::fmax(0.0, one_minus_cos * (2.0 - one_minus_cos)));
    const double phi = 2.0 * kPi * u2;
    const Frame f(to_c / d);
    s.wi = glm::normalize(f.to_world(Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t)));
    const double t = intersect_front(Ray{x, s.wi});
    // Grazing directions can miss by rounding; place them at the tangent distance.
    s.dist = t > 0.0 ? t : std::sqrt(std::fmax(0.0, d2 - m_r * m_r));
    s.L = m_L;
    s.pdf = 1.0 / (2.0 * kPi * one_minus_cos_max);
    return s;
  }

 private:
  Vec3 m_c{0.0};
  double m_r = 1.0;
  Color m_L{0.0};
};

static_assert(std::is_trivially_copyable_v<RectLight>);
static_assert(std::is_trivially_copyable_v<SphereLight>);

}  // namespace tessera
