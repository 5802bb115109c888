#pragma once
/// The sphere light kind: a sphere emitting outward (SphereLightDesc in lights.h), its checks
/// for prepare() and its prepared class: intersection, cone sampling and solid-angle pdf.
#include "lights/light_kind.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace tessera {

class SphereLight {
 public:
  SphereLight() = default;
  explicit SphereLight(const SphereLightDesc& d) : m_c(d.center), m_r(d.radius), m_L(d.radiance) {
    if (!(d.radius > 0.0) || !std::isfinite(d.radius))
      throw std::invalid_argument("sphere light: radius " + std::to_string(d.radius) + " must be finite and > 0");
  }
  /// Distance to the outward-facing (front) hit, or -1. From inside there is none.
  TESSERA_HOST_DEVICE double intersect_front(const Ray& r) const {
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
  TESSERA_HOST_DEVICE Color radiance() const { return m_L; }
  TESSERA_HOST_DEVICE Color radiance(const Vec3&) const { return m_L; }  ///< the same in every direction
  void bounds(Vec3* lo, Vec3* hi) const {
    *lo = m_c - Vec3(m_r);
    *hi = m_c + Vec3(m_r);
  }
  /// Uniform sampling of the visible cone.
  TESSERA_HOST_DEVICE double pdf(const Vec3& x, const Vec3&, double) const {
    const double d2 = glm::dot(x - m_c, x - m_c);
    if (d2 <= m_r * m_r) return 0.0;
    const double sin2 = m_r * m_r / d2;
    const double one_minus_cos = sin2 / (1.0 + std::sqrt(1.0 - sin2));
    return 1.0 / (2.0 * kPi * one_minus_cos);
  }
  TESSERA_HOST_DEVICE LightSample sample(const Vec3& x, double u1, double u2) const {
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

static_assert(std::is_trivially_copyable_v<SphereLight>);

template <>
struct LightKind<SphereLightDesc> {
  using Kernel = SphereLight;
  static constexpr const char* kName = "sphere light";
  template <class Check>
  static void validate(const SphereLightDesc& l, const Check& c) {
    c.point("position", l.center);
    c.length("radius", l.radius);
    c.radiance(l.radiance);
  }
};

}  // namespace tessera
