#pragma once
/// Environment's lookups (eval, sample, pdf): their one definition, for the host and the
/// device. Included by environment.cpp (the host's out-of-line symbols, as before) and by the
/// CUDA translation units in their device pass only (core/src/cuda/). An envmap's tables are
/// read through m_texel and m_dist, which point at the host's tables or, in a relocated copy,
/// at the GPU's copies of them (cuda/device_scene.cpp).
#include "lights/environment.h"
#include "sampling/warp.h"

namespace tessera {

TESSERA_HOST_DEVICE void Environment::to_uv(const Vec3& d, double* u, double* v) const {
  const Vec3 l = m_frame.to_local(d);
  const double theta = std::atan2(std::hypot(l.x, l.y), l.z);  // exact near the poles, unlike acos
  double phi = std::atan2(l.y, l.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  *u = std::min(phi / (2.0 * kPi), 1.0 - 1e-16);
  *v = std::min(theta / kPi, 1.0 - 1e-16);
}

TESSERA_HOST_DEVICE Color Environment::eval(const Vec3& d) const {
  switch (m_type) {
    case BackgroundType::Constant: return m_color;
    case BackgroundType::Gradient: {
      const double t = glm::dot(d, m_frame.n);
      return t >= 0.0 ? m_middle * (1.0 - t) + m_top * t : m_middle * (1.0 + t) + m_bottom * (-t);
    }
    case BackgroundType::EnvMap:
    default: {
      double u, v;
      to_uv(d, &u, &v);
      const int x = std::min(m_w - 1, static_cast<int>(u * m_w));
      const int y = std::min(m_h - 1, static_cast<int>(v * m_h));
      return m_texel[static_cast<std::size_t>(y) * m_w + x];
    }
  }
}

TESSERA_HOST_DEVICE Color Environment::sample(double u1, double u2, Vec3* d, double* pdf) const {
  if (m_zonal_ok) {
    *d = m_frame.to_world(sphere_direction(m_zonal.sample_t(u1), u2));
    *pdf = Environment::pdf(*d);  // from the direction, as MIS reads it
    return eval(*d);
  }
  if (m_type != BackgroundType::EnvMap) {
    *d = uniform_sphere(u1, u2);
    *pdf = uniform_sphere_pdf();
    return eval(*d);
  }
  double u, v;
  const double pdf_uv = m_dist.sample(u1, u2, &u, &v);
  const double theta = v * kPi, phi = u * 2.0 * kPi;
  const double sin_theta = std::sin(theta);
  if (pdf_uv <= 0.0 || sin_theta <= 0.0) {
    *pdf = 0.0;
    return Color(0.0);
  }
  *d = m_frame.to_world(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), std::cos(theta)));
  *pdf = pdf_uv / (2.0 * kPi * kPi * sin_theta);
  return eval(*d);
}

TESSERA_HOST_DEVICE double Environment::pdf(const Vec3& d) const {
  if (m_zonal_ok) return m_zonal.pdf_t(glm::dot(d, m_frame.n)) * (0.5 * kInvPi);
  if (m_type != BackgroundType::EnvMap) return uniform_sphere_pdf();
  double u, v;
  to_uv(d, &u, &v);
  const double sin_theta = std::sin(v * kPi);
  if (sin_theta <= 0.0) return 0.0;
  return m_dist.pdf(u, v) / (2.0 * kPi * kPi * sin_theta);
}

}  // namespace tessera
