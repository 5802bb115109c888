#pragma once
/// The rect light kind: a one-sided rectangle (RectLightDesc in lights.h), its checks for
/// prepare() and its prepared class: intersection, sampling and solid-angle pdf.
#include "lights/light_kind.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace tessera {

class RectLight {
 public:
  RectLight() = default;
  explicit RectLight(const RectLightDesc& d) : m_c(d.position), m_L(d.radiance) {
    const Vec3 to = d.target - d.position;
    if (!(glm::length(to) > 0.0)) throw std::invalid_argument("rect light: target equals position");
    if (!(d.width > 0.0) || !(d.height > 0.0) || !std::isfinite(d.width) || !std::isfinite(d.height))
      throw std::invalid_argument("rect light: size " + std::to_string(d.width) + " x " + std::to_string(d.height) +
                                  " must be finite and > 0");
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
  TESSERA_HOST_DEVICE double intersect_front(const Ray& r) const {
    const double dn = glm::dot(r.d, m_n);
    if (!(dn < 0.0)) return -1.0;  // the front emits toward +n: a ray must travel against n
    const double t = glm::dot(m_c - r.o, m_n) / dn;
    if (!(t > 0.0)) return -1.0;
    const Vec3 p = r.o + t * r.d - m_c;
    if (std::fabs(glm::dot(p, m_u)) > m_hw || std::fabs(glm::dot(p, m_v)) > m_hh) return -1.0;
    return t;
  }
  static constexpr bool kInfinite = false;
  TESSERA_HOST_DEVICE Color radiance() const { return m_L; }
  TESSERA_HOST_DEVICE Color radiance(const Vec3&) const { return m_L; }  ///< the same in every direction
  /// A world box holding the rectangle: the centre +- half its diagonal on every axis.
  void bounds(Vec3* lo, Vec3* hi) const {
    *lo = m_c - Vec3(m_reach);
    *hi = m_c + Vec3(m_reach);
  }
  TESSERA_HOST_DEVICE double pdf(const Vec3& x, const Vec3& wi, double t) const {
    const double cos_l = -glm::dot(wi, m_n);
    return cos_l > 0.0 ? t * t / (cos_l * m_area) : 0.0;
  }
  TESSERA_HOST_DEVICE LightSample sample(const Vec3& x, double u1, double u2) const {
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

static_assert(std::is_trivially_copyable_v<RectLight>);

template <>
struct LightKind<RectLightDesc> {
  using Kernel = RectLight;
  static constexpr const char* kName = "rect light";
  template <class Check>
  static void validate(const RectLightDesc& l, const Check& c) {
    c.point("position", l.position);
    c.point("target", l.target);
    c.length("width", l.width);
    c.length("height", l.height);
    c.radiance(l.radiance);
  }
};

}  // namespace tessera
