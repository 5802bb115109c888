#pragma once
/// ZonalLinear: a density over the unit sphere that depends only on t = cos(angle to an axis)
/// and is linear in t on each hemisphere, the shape of a gradient background's radiance
/// (docs/physics.md section 7):
///
///   g(t) = mid + (top - mid) t      for t >= 0,
///   g(t) = mid + (bottom - mid) (-t) for t < 0,   top, mid, bottom >= 0.
///
/// Directions are uniform in azimuth, and t has density g(t) / G on [-1, 1] with
/// G = (top + 2 mid + bottom) / 2, so the solid-angle pdf is g(t) / (2 pi G) (dw = dt dphi).
/// The weights are stored divided by the largest, so any finite scale samples the same
/// directions. Sampling inverts the CDF in closed form, in a form without cancellation.
#include <tessera/math.h>

#include <algorithm>
#include <cmath>

namespace tessera {

class ZonalLinear {
 public:
  ZonalLinear() = default;
  /// False (and the density unusable) unless the weights are finite, >= 0 and not all 0.
  bool init(double top, double mid, double bottom) {
    const double w = std::max({top, mid, bottom});
    if (!(w > 0.0) || !std::isfinite(w) || !(std::min({top, mid, bottom}) >= 0.0)) return false;
    m_top = top / w;
    m_mid = mid / w;
    m_bot = bottom / w;
    const double up = 0.5 * (m_mid + m_top), down = 0.5 * (m_mid + m_bot);
    m_norm = up + down;  // >= 0.5: the largest weight is 1
    m_p_up = up / m_norm;
    return true;
  }

  /// t in [-1, 1] with density g(t) / G, from one uniform u in [0, 1).
  TESSERA_HOST_DEVICE double sample_t(double u) const {
    const bool upper = u < m_p_up;  // m_p_up is 0 when the upper half has no weight: never taken
    const double v = std::clamp(upper ? u / m_p_up : (u - m_p_up) / (1.0 - m_p_up), 0.0, 1.0);
    const double e = upper ? m_top : m_bot;
    // s in [0, 1] with density proportional to mid + (e - mid) s: the root of
    // (e - mid) s^2 + 2 mid s = v (mid + e), written as v (mid + e) / (mid + sqrt(...))
    const double den = m_mid + std::sqrt(m_mid * m_mid * (1.0 - v) + v * e * e);
    const double s = den > 0.0 ? std::min(1.0, v * (m_mid + e) / den) : v;
    return upper ? s : -s;
  }

  /// The density of t on [-1, 1] (the solid-angle pdf is this / (2 pi)).
  TESSERA_HOST_DEVICE double pdf_t(double t) const {
    const double g = t >= 0.0 ? m_mid + (m_top - m_mid) * t : m_mid + (m_bot - m_mid) * (-t);
    return std::max(g, 0.0) / m_norm;
  }

 private:
  double m_top = 1.0, m_mid = 1.0, m_bot = 1.0, m_norm = 2.0, m_p_up = 0.5;
};

}  // namespace tessera
