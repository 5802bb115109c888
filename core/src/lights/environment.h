#pragma once
/// The background light: constant (sampled uniformly over the sphere), gradient (sampled in
/// proportion to a linear bound of its largest colour component in t = d.up on each hemisphere:
/// sampling/zonal_linear.h), or an equirectangular environment map with importance sampling
/// proportional to max(RGB) * sin(theta).
///
/// Envmap mapping (docs/physics.md): in the frame (s, t, n = up) of tessera::Frame(up),
/// theta = acos(d.n) in [0, pi], phi = atan2(d.t, d.s) wrapped to [0, 2 pi);
/// column = phi / (2 pi) * width, row = theta / pi * height (row 0 = the up pole). Texels are
/// piecewise constant (nearest), so sampling pdf and evaluation agree exactly.
#include <tessera/lights.h>
#include <tessera/math.h>

#include "sampling/distribution.h"
#include "sampling/zonal_linear.h"

#include <memory>
#include <span>
#include <vector>

namespace tessera {

class Environment {
 public:
  Environment() = default;
  /// Throws std::invalid_argument on an envmap type with no image or a non-finite texel.
  explicit Environment(const BackgroundDesc& desc);

  /// Radiance arriving along the direction -d, i.e. seen looking along unit d.
  /// eval, sample and pdf are host and device code: one definition (environment_eval.h).
  TESSERA_HOST_DEVICE Color eval(const Vec3& d) const;
  /// Sample a direction; returns radiance, sets *d and *pdf (solid angle). pdf 0 = failed.
  TESSERA_HOST_DEVICE Color sample(double u1, double u2, Vec3* d, double* pdf) const;
  TESSERA_HOST_DEVICE double pdf(const Vec3& d) const;
  /// False when the background is black everywhere: it is then not a light to sample.
  TESSERA_HOST_DEVICE bool emits() const { return m_emits; }
  TESSERA_HOST_DEVICE bool visible() const { return m_visible; }

  /// An envmap's tables (texels, row-major from the up pole; the sampling distribution's
  /// table, Distribution2D's layout): empty for the other backgrounds. Host memory, shared by
  /// the copies of this Environment.
  std::span<const Color> texels() const;
  std::span<const double> distribution_table() const;
  /// A copy that reads its envmap tables at `texels` and `table` (copies of the two spans
  /// above, e.g. on a GPU) and owns nothing: for a device copy of this object's bytes.
  Environment relocated(const Color* texels, const double* table) const;

 private:
  BackgroundType m_type = BackgroundType::Constant;
  Color m_color{0.0}, m_top{0.0}, m_middle{0.0}, m_bottom{0.0};
  Frame m_frame{Vec3(0.0, 0.0, 1.0)};
  bool m_emits = false, m_visible = true;
  int m_w = 0, m_h = 0;
  /// An envmap's tables, owned on the host (null for the other backgrounds and in relocated
  /// copies); the lookups read them through m_texel and m_dist only
  struct Tables {
    std::vector<Color> texels;
    Distribution2D dist;
  };
  std::shared_ptr<const Tables> m_tables;
  const Color* m_texel = nullptr;
  Distribution2DView m_dist;
  ZonalLinear m_zonal;      // a gradient's sampling density
  bool m_zonal_ok = false;  // false: sampled uniformly (a constant, or weights that overflow)
  TESSERA_HOST_DEVICE void to_uv(const Vec3& d, double* u, double* v) const;
};

}  // namespace tessera
