#include "lights/environment.h"

#include "sampling/warp.h"

#include <stdexcept>

namespace tessera {

Environment::Environment(const BackgroundDesc& desc)
    : m_type(desc.type),
      m_frame(glm::length(desc.up) > 0.0 ? glm::normalize(desc.up) : Vec3(0, 0, 1)),
      m_visible(desc.visible) {
  if (!(desc.intensity >= 0.0) || !std::isfinite(desc.intensity))
    throw std::invalid_argument("background: intensity must be finite and >= 0");
  if (!(glm::length(desc.up) > 0.0)) throw std::invalid_argument("background: up is the zero vector");
  const double k = desc.intensity;
  switch (m_type) {
    case BackgroundType::Constant:
      m_color = desc.color * k;
      m_emits = !is_black(m_color);
      break;
    case BackgroundType::Gradient:
      m_top = desc.top * k;
      m_middle = desc.middle * k;
      m_bottom = desc.bottom * k;
      m_emits = !(is_black(m_top) && is_black(m_middle) && is_black(m_bottom));
      // max(RGB) of a linear mix is at most the mix of the ends' max(RGB), and 0 only where
      // the colour is black: the density covers every direction the radiance is not 0 in.
      m_zonal_ok = m_emits && m_zonal.init(max_component(m_top), max_component(m_middle), max_component(m_bottom));
      break;
    case BackgroundType::EnvMap: {
      if (!desc.envmap || desc.envmap->width < 1 || desc.envmap->height < 1)
        throw std::invalid_argument("background: envmap has no image");
      const Image& img = *desc.envmap;
      m_w = img.width;
      m_h = img.height;
      m_texels.resize(static_cast<std::size_t>(m_w) * m_h);
      std::vector<double> f(m_texels.size());
      for (int y = 0; y < m_h; ++y) {
        const double sin_theta = std::sin(kPi * (y + 0.5) / m_h);
        for (int x = 0; x < m_w; ++x) {
          const float* p = img.px(x, y);
          const Color c = Color(p[0], p[1], p[2]) * k;
          if (!is_finite(c) || c.x < 0 || c.y < 0 || c.z < 0)
            throw std::invalid_argument("background: envmap texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                        ") is negative or not finite");
          const std::size_t i = static_cast<std::size_t>(y) * m_w + x;
          m_texels[i] = c;
          f[i] = max_component(c) * sin_theta;
        }
      }
      m_dist = Distribution2D(f, m_w, m_h);
      m_emits = m_dist.integral() > 0.0;
      break;
    }
  }
}

void Environment::to_uv(const Vec3& d, double* u, double* v) const {
  const Vec3 l = m_frame.to_local(d);
  const double theta = std::atan2(std::hypot(l.x, l.y), l.z);  // exact near the poles, unlike acos
  double phi = std::atan2(l.y, l.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  *u = std::min(phi / (2.0 * kPi), 1.0 - 1e-16);
  *v = std::min(theta / kPi, 1.0 - 1e-16);
}

Color Environment::eval(const Vec3& d) const {
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
      return m_texels[static_cast<std::size_t>(y) * m_w + x];
    }
  }
}

Color Environment::sample(double u1, double u2, Vec3* d, double* pdf) const {
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

double Environment::pdf(const Vec3& d) const {
  if (m_zonal_ok) return m_zonal.pdf_t(glm::dot(d, m_frame.n)) * (0.5 * kInvPi);
  if (m_type != BackgroundType::EnvMap) return uniform_sphere_pdf();
  double u, v;
  to_uv(d, &u, &v);
  const double sin_theta = std::sin(v * kPi);
  if (sin_theta <= 0.0) return 0.0;
  return m_dist.pdf(u, v) / (2.0 * kPi * kPi * sin_theta);
}

}  // namespace tessera
