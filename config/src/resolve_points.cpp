// Points and orbits resolved against the data bounds (conventions in build_scene.h).
#include <tessera/config/build_scene.h>

#include "yaml_reader.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tessera::config {

Vec3 orbit_direction(const OrbitSpec& orbit, const Vec3& up_in) {
  if (orbit.moves()) throw std::logic_error("orbit_direction: a moving orbit needs its step (OrbitSpec::at)");
  const Vec3 up = glm::normalize(up_in);

  // Reference e1: the world axis least aligned with up, projected onto the plane normal to up
  const Vec3 a = glm::abs(up);
  const int axis = (a.x <= a.y && a.x <= a.z) ? 0 : (a.y <= a.z ? 1 : 2);
  Vec3 ref(0.0);
  ref[axis] = 1.0;
  const Vec3 e1 = glm::normalize(ref - glm::dot(ref, up) * up);
  const Vec3 e2 = glm::cross(up, e1);

  // An azimuth whose radians would overflow (|azimuth| > 5.7e307) is first reduced exactly
  // modulo 360 (any other azimuth as before: its radians are finite)
  const double az_deg = orbit.azimuth.start;
  const double az = (std::isfinite(az_deg * kPi) ? az_deg : std::fmod(az_deg, 360.0)) * kPi / 180.0;
  const double el = orbit.elevation.start * kPi / 180.0;
  return std::cos(el) * (std::cos(az) * e1 + std::sin(az) * e2) + std::sin(el) * up;
}

double fit_distance(double fov_deg, int width, int height) {
  if (!(fov_deg > 0.0 && fov_deg < 180.0))
    throw std::invalid_argument("distance: fit: fov " + format_number(fov_deg) + " is outside (0, 180) degrees");
  if (width < 1 || height < 1)
    throw std::invalid_argument("distance: fit: image size " + std::to_string(width) + "x" + std::to_string(height) +
                                " must be at least 1x1");
  // The camera's image plane spans tan(fov/2) vertically and aspect times that horizontally
  const double tan_v = std::tan(0.5 * fov_deg * kPi / 180.0);
  const double tan_h = tan_v * static_cast<double>(width) / height;
  const double half_min = std::atan(std::min(tan_v, tan_h));
  // The sphere is tangent to the two frustum planes of the narrower field of view
  return 1.0 / std::sin(half_min);
}

Vec3 resolve_point(const PointSpec& p, const Bounds& data_bounds, const Vec3& up) {
  if (p.is_fit()) throw std::logic_error("resolve_point: an orbit with distance: fit needs the camera's fit distance");
  return resolve_point(p, data_bounds, up, 1.0);
}

Vec3 resolve_point(const PointSpec& p, const Bounds& data_bounds, const Vec3& up, double fit_radii) {
  switch (p.kind) {
    case PointSpec::Kind::Absolute: return p.xyz;
    case PointSpec::Kind::Center: return data_bounds.center();
    case PointSpec::Kind::Orbit: {
      const double radii = p.orbit.fit ? fit_radii : p.orbit.distance.start;
      return data_bounds.center() + radii * data_bounds.radius() * orbit_direction(p.orbit, up);
    }
  }
  return p.xyz;
}

}  // namespace tessera::config
