#include "lights/environment.h"

#include "lights/environment_eval.h"

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
      auto tables = std::make_shared<Tables>();
      std::vector<Color>& texels = tables->texels;
      texels.resize(static_cast<std::size_t>(m_w) * m_h);
      std::vector<double> f(texels.size());
      for (int y = 0; y < m_h; ++y) {
        const double sin_theta = std::sin(kPi * (y + 0.5) / m_h);
        for (int x = 0; x < m_w; ++x) {
          const float* p = img.px(x, y);
          const Color c = Color(p[0], p[1], p[2]) * k;
          if (!is_finite(c) || c.x < 0 || c.y < 0 || c.z < 0)
            throw std::invalid_argument("background: envmap texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                        ") is negative or not finite");
          const std::size_t i = static_cast<std::size_t>(y) * m_w + x;
          texels[i] = c;
          f[i] = max_component(c) * sin_theta;
        }
      }
      tables->dist = Distribution2D(f, static_cast<std::size_t>(m_w), static_cast<std::size_t>(m_h));
      m_texel = tables->texels.data();
      m_dist = tables->dist.view();
      m_tables = std::move(tables);
      m_emits = m_dist.integral() > 0.0;
      break;
    }
  }
}

std::span<const Color> Environment::texels() const {
  return m_tables ? std::span<const Color>(m_tables->texels) : std::span<const Color>();
}

std::span<const double> Environment::distribution_table() const {
  return m_tables ? std::span<const double>(m_tables->dist.table()) : std::span<const double>();
}

Environment Environment::relocated(const Color* texels, const double* table) const {
  Environment e = *this;
  e.m_tables.reset();
  if (m_type == BackgroundType::EnvMap) {
    e.m_texel = texels;
    e.m_dist.t = table;
  }
  return e;
}

}  // namespace tessera
