#pragma once
/// Camera::generate, the primary ray of a pixel sample: its one definition, for the host and
/// the device. Included by camera.cpp (the host's out-of-line symbol, as before) and by the
/// CUDA translation units in their device pass only (core/src/cuda/), so that the host symbol
/// stays camera.cpp's and the device code inlines this body.
#include <tessera/camera.h>

#include "sampling/warp.h"

namespace tessera {

TESSERA_HOST_DEVICE Ray Camera::generate(double px, double py, double lx, double ly) const {
  // Pinhole direction through the image-plane point.
  const double sx = (2.0 * px / m_width - 1.0) * m_tan_half * m_aspect;
  const double sy = (1.0 - 2.0 * py / m_height) * m_tan_half;
  const Vec3 d = glm::normalize(m_forward + sx * m_right + sy * m_up);
  if (m_aperture <= 0.0) return Ray{m_pos, d};
  // Thin lens: every ray through the lens meets the pinhole ray on the focal plane.
  const Vec3 focus_point = m_pos + d * (m_focus / glm::dot(d, m_forward));
  const Vec2 lens = concentric_disk(lx, ly) * m_aperture;
  const Vec3 o = m_pos + lens.x * m_right + lens.y * m_up;
  return Ray{o, glm::normalize(focus_point - o)};
}

}  // namespace tessera
