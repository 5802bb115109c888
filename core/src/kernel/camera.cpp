#include <tessera/camera.h>

#include "kernel/camera_ray.h"
#include "sampling/warp.h"

#include <stdexcept>
#include <string>

namespace tessera {

Camera::Camera(const CameraDesc& c, int width, int height) {
  if (width < 1 || height < 1)
    throw std::invalid_argument("camera: image size " + std::to_string(width) + "x" + std::to_string(height) +
                                " must be at least 1x1");
  if (!is_finite(c.position) || !is_finite(c.look_at) || !is_finite(c.up))
    throw std::invalid_argument("camera: position, look_at and up must be finite");
  if (!(c.fov_deg > 0.0 && c.fov_deg < 180.0))
    throw std::invalid_argument("camera: fov " + std::to_string(c.fov_deg) + " is outside (0, 180) degrees");
  if (!(c.aperture >= 0.0) || !std::isfinite(c.aperture))
    throw std::invalid_argument("camera: aperture must be finite and >= 0");
  if (!(c.focus_distance >= 0.0) || !std::isfinite(c.focus_distance))
    throw std::invalid_argument("camera: focus_distance must be finite and >= 0");
  const Vec3 view = c.look_at - c.position;
  const double dist = glm::length(view);
  if (!std::isfinite(dist))
    throw std::invalid_argument("camera: the distance from position to look_at overflows (position too far "
                                "from look_at)");
  if (!(dist > 0.0)) throw std::invalid_argument("camera: position equals look_at");
  m_forward = view / dist;
  const double up_len = glm::length(c.up);
  if (!(up_len > 0.0)) throw std::invalid_argument("camera: up is the zero vector");
  const Vec3 r = glm::cross(m_forward, c.up / up_len);
  if (glm::length(r) < 1e-9)
    throw std::invalid_argument("camera: up is parallel to the view direction (look_at - position)");
  m_right = glm::normalize(r);
  m_up = glm::cross(m_right, m_forward);
  m_pos = c.position;
  m_tan_half = std::tan(0.5 * c.fov_deg * kPi / 180.0);
  m_aspect = static_cast<double>(width) / height;
  m_aperture = c.aperture;
  m_focus = c.focus_distance > 0.0 ? c.focus_distance : dist;
  m_width = width;
  m_height = height;
}

bool Camera::project(const Vec3& p, double* px, double* py) const {
  const Vec3 v = p - m_pos;
  const double z = glm::dot(v, m_forward);
  if (!(z > 1e-12 * (1.0 + glm::length(v)))) return false;
  const double sx = glm::dot(v, m_right) / z, sy = glm::dot(v, m_up) / z;
  *px = (sx / (m_tan_half * m_aspect) + 1.0) * 0.5 * m_width;
  *py = (1.0 - sy / m_tan_half) * 0.5 * m_height;
  return true;
}

}  // namespace tessera
