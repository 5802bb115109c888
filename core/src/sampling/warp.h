#pragma once
/// Warps from [0,1)^2 to common domains, with their pdfs.
#include <tessera/math.h>

namespace tessera {

/// Shirley-Chiu concentric map of the unit square onto the unit disk.
TESSERA_HOST_DEVICE inline Vec2 concentric_disk(double u1, double u2) {
  const double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
  if (a == 0.0 && b == 0.0) return Vec2(0.0);
  double r, phi;
  if (std::fabs(a) > std::fabs(b)) {
    r = a;
    phi = (kPi / 4.0) * (b / a);
  } else {
    r = b;
    phi = (kPi / 2.0) - (kPi / 4.0) * (a / b);
  }
  return Vec2(r * std::cos(phi), r * std::sin(phi));
}

/// The unit vector with z-component z in [-1, 1] at azimuth 2 pi u2 about +z.
TESSERA_HOST_DEVICE inline Vec3 sphere_direction(double z, double u2) {
  const double r = std::sqrt(std::fmax(0.0, 1.0 - z * z));
  const double phi = 2.0 * kPi * u2;
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

TESSERA_HOST_DEVICE inline Vec3 uniform_sphere(double u1, double u2) { return sphere_direction(1.0 - 2.0 * u1, u2); }
TESSERA_HOST_DEVICE inline constexpr double uniform_sphere_pdf() { return kInv4Pi; }

/// Cosine-weighted hemisphere about +z; pdf = cos(theta) / pi.
TESSERA_HOST_DEVICE inline Vec3 cosine_hemisphere(double u1, double u2) {
  const Vec2 d = concentric_disk(u1, u2);
  const double z = std::sqrt(std::fmax(0.0, 1.0 - d.x * d.x - d.y * d.y));
  return Vec3(d.x, d.y, z);
}

}  // namespace tessera
