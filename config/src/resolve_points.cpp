// Points and orbits resolved against the data bounds (conventions in build_scene.h).
#include <tessera/config/build_scene.h>

#include <cmath>

namespace tessera::config {

Vec3 orbit_direction(const OrbitSpec& orbit, const Vec3& up_in) {
  const Vec3 up = glm::normalize(up_in);

  // Reference e1: the world axis least aligned with up, projected onto the plane normal to up
  const Vec3 a = glm::abs(up);
  const int axis = (a.x <= a.y && a.x <= a.z) ? 0 : (a.y <= a.z ? 1 : 2);
  Vec3 ref(0.0);
  ref[axis] = 1.0;
  const Vec3 e1 = glm::normalize(ref - glm::dot(ref, up) * up);
  const Vec3 e2 = glm::cross(up, e1);

  const double az = orbit.azimuth * kPi / 180.0;
  const double el = orbit.elevation * kPi / 180.0;
  return std::cos(el) * (std::cos(az) * e1 + std::sin(az) * e2) + std::sin(el) * up;
}

Vec3 resolve_point(const PointSpec& p, const Bounds& data_bounds, const Vec3& up) {
  switch (p.kind) {
    case PointSpec::Kind::Absolute: return p.xyz;
    case PointSpec::Kind::Center: return data_bounds.center();
    case PointSpec::Kind::Orbit:
      return data_bounds.center() +
             p.orbit.distance * data_bounds.radius() * orbit_direction(p.orbit, up);
  }
  return p.xyz;
}

}  // namespace tessera::config
