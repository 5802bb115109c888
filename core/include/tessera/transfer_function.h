#pragma once
/// Piecewise-linear transfer functions of the normalised value u in [0, 1], clamped at the
/// ends. Stored inline (no heap) so that kernels can copy them; at most kMaxPoints points.
#include <tessera/host_device.h>
#include <tessera/math.h>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace tessera {

inline constexpr int kMaxTfPoints = 64;
/// Bins of [0, 1) in a ScalarTF's segment table (detail::tf_eval_binned).
inline constexpr int kTfBins = 256;

namespace detail {
/// Index i such that x[i] <= u < x[i+1], for n >= 2 and x[0] <= u < x[n-1].
TESSERA_HOST_DEVICE inline int tf_segment(const double* x, int n, double u) {
  int lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (x[mid] <= u) lo = mid;
    else hi = mid;
  }
  return lo;
}

/// Piecewise-linear interpolation through (x[i], v[i]), clamped at the ends; zero if n == 0.
/// Inline: it is evaluated at every density lookup of the render loop.
template <class V>
TESSERA_HOST_DEVICE inline V tf_eval(const double* x, const V* v, int n, double u) {
  if (n == 0) return V(0.0);
  if (u <= x[0]) return v[0];
  if (u >= x[n - 1]) return v[n - 1];
  const int i = tf_segment(x, n, u);
  const double w = x[i + 1] - x[i];
  const double t = w > 0.0 ? (u - x[i]) / w : 1.0;
  return v[i] * (1.0 - t) + v[i + 1] * t;
}

/// tf_eval with a segment table: seg[b] is the segment of u = b / kTfBins (clamped into the
/// points' range), so the segment of any u in [0, 1) is found by a table load and a forward
/// walk over the points inside its bin (usually none) instead of a binary search. The same
/// segment, hence the same result bit for bit, as tf_eval.
template <class V>
[[gnu::always_inline]] TESSERA_HOST_DEVICE inline V tf_eval_binned(const double* x, const V* v, const std::uint8_t* seg,
                                                                   int n, double u) {
  if (n == 0) return V(0.0);
  if (u <= x[0]) return v[0];
  if (u >= x[n - 1]) return v[n - 1];
  int i;
  if (u >= 0.0 && u < 1.0) {
    i = seg[static_cast<int>(u * kTfBins)];
    while (x[i + 1] <= u) ++i;
  } else {
    i = tf_segment(x, n, u);
  }
  const double w = x[i + 1] - x[i];
  const double t = w > 0.0 ? (u - x[i]) / w : 1.0;
  return v[i] * (1.0 - t) + v[i + 1] * t;
}
}  // namespace detail

/// Scalar TF. Points must have non-decreasing x (equal x allowed: a step). Empty = zero.
class ScalarTF {
 public:
  ScalarTF() = default;
  /// Throws std::invalid_argument if more than kMaxTfPoints points, x decreasing or non-finite.
  ScalarTF(const std::vector<double>& xs, const std::vector<double>& vs);
  static ScalarTF constant(double v) { return ScalarTF({0.0}, {v}); }

  /// Inline, table-driven (detail::tf_eval_binned): the opacity is evaluated at every lookup.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE double eval(double u) const {
    return detail::tf_eval_binned(m_x, m_v, m_seg, m_n, u);
  }
  /// Exact maximum of the TF over [u0, u1] (u0 <= u1), from the end values and the points
  /// strictly inside: a piecewise-linear function peaks at a point or an end.
  double max_over(double u0, double u1) const;
  double max_value() const;
  bool is_zero() const;
  int size() const { return m_n; }
  double x(int i) const { return m_x[i]; }
  double v(int i) const { return m_v[i]; }

 private:
  int m_n = 0;
  double m_x[kMaxTfPoints] = {};
  double m_v[kMaxTfPoints] = {};
  std::uint8_t m_seg[kTfBins] = {};  ///< segment of u = b / kTfBins (tf_eval_binned)
};

/// RGB TF; same rules as ScalarTF.
class ColorTF {
 public:
  ColorTF() = default;
  ColorTF(const std::vector<double>& xs, const std::vector<Color>& vs);
  static ColorTF constant(const Color& c) { return ColorTF({0.0}, {c}); }

  TESSERA_HOST_DEVICE Color eval(double u) const { return detail::tf_eval(m_x, m_v, m_n, u); }
  bool is_zero() const;
  int size() const { return m_n; }

 private:
  int m_n = 0;
  double m_x[kMaxTfPoints] = {};
  Color m_v[kMaxTfPoints] = {};
};

/// Everything that maps a field value to optical properties (docs/physics.md "Field and medium").
struct TransferFunction {
  double lo = 0.0, hi = 1.0;   ///< value range mapped to u = 0 .. 1 (lo < hi)
  double density_scale = 1.0;  ///< sigma_t = density_scale * opacity(u), 1/world unit
  ScalarTF opacity;
  ColorTF diffuse = ColorTF::constant(Color(1.0));
  ColorTF specular;  ///< absent = zero
  ScalarTF roughness = ScalarTF::constant(0.5);
  ColorTF emission;  ///< absent = zero

  /// u(v) = clamp((v - lo)/(hi - lo), 0, 1); NaN maps to 0 (no medium), see docs/physics.md.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE double normalise(double v) const {
    if (!(v == v)) return 0.0;
    const double u = (v - lo) / (hi - lo);
    return u <= 0.0 ? 0.0 : (u >= 1.0 ? 1.0 : u);
  }
};
static_assert(std::is_trivially_copyable_v<TransferFunction>);

}  // namespace tessera
