#pragma once
/// Henyey-Greenstein phase function. Directions follow the light: `d_in` is the direction the
/// path travelled into the collision, `d_out` the one it leaves in; cos theta = dot(d_in, d_out),
/// so g > 0 scatters forward.
#include <tessera/math.h>

namespace tessera {

TESSERA_HOST_DEVICE inline double hg_eval(double cos_theta, double g) {
  const double denom = 1.0 + g * g - 2.0 * g * cos_theta;
  return kInv4Pi * (1.0 - g * g) / (denom * std::sqrt(denom));
}

/// Sample d_out given d_in; returns its pdf (= the phase function value).
TESSERA_HOST_DEVICE inline double hg_sample(const Vec3& d_in, double g, double u1, double u2, Vec3* d_out) {
  double cos_theta;
  if (std::fabs(g) < 1e-3) {
    cos_theta = 1.0 - 2.0 * u1;
  } else {
    const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u1);
    cos_theta = (1.0 + g * g - s * s) / (2.0 * g);
  }
  cos_theta = std::clamp(cos_theta, -1.0, 1.0);
  const double sin_theta = std::sqrt(std::fmax(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * kPi * u2;
  const Frame f(d_in);
  *d_out = f.to_world(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
  return hg_eval(cos_theta, g);
}

}  // namespace tessera
