#pragma once
/// Small math vocabulary shared by the renderer. All geometry and radiometry run in double
/// precision: the hot loop is scalar, where double costs little, and it keeps volume-local
/// coordinates exact for data placed far from the origin.
#include <tessera/host_device.h>

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

namespace tessera {

using Vec3 = glm::dvec3;
using Vec2 = glm::dvec2;
using Color = glm::dvec3;  ///< linear RGB radiance or reflectance

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInvPi = 1.0 / kPi;
inline constexpr double kInv4Pi = 1.0 / (4.0 * kPi);

TESSERA_HOST_DEVICE inline double max_component(const Vec3& v) { return std::fmax(v.x, std::fmax(v.y, v.z)); }
TESSERA_HOST_DEVICE inline double luminance(const Color& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
TESSERA_HOST_DEVICE inline bool is_black(const Color& c) { return c.x == 0.0 && c.y == 0.0 && c.z == 0.0; }
TESSERA_HOST_DEVICE inline bool is_finite(const Color& c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
}

/// Orthonormal basis around unit vector n (Duff et al. 2017, branchless).
struct Frame {
  Vec3 s, t, n;
  TESSERA_HOST_DEVICE explicit Frame(const Vec3& nn) : n(nn) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    s = Vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = Vec3(b, sign + n.y * n.y * a, -n.y);
  }
  TESSERA_HOST_DEVICE Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
  TESSERA_HOST_DEVICE Vec3 to_local(const Vec3& v) const {
    return Vec3(glm::dot(v, s), glm::dot(v, t), glm::dot(v, n));
  }
};

/// A ray o + t d with unit direction d; t is a world distance.
struct Ray {
  Vec3 o;
  Vec3 d;
};

}  // namespace tessera
