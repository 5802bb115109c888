#include <tessera/transfer_function.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace tessera {
namespace {

void check_points(const std::vector<double>& xs, std::size_t nv) {
  if (xs.size() != nv) throw std::invalid_argument("transfer function: x and value counts differ");
  if (xs.size() > static_cast<std::size_t>(kMaxTfPoints))
    throw std::invalid_argument("transfer function: " + std::to_string(xs.size()) +
                                " points, at most " + std::to_string(kMaxTfPoints) + " allowed");
  for (std::size_t i = 0; i < xs.size(); ++i) {
    if (!std::isfinite(xs[i]))
      throw std::invalid_argument("transfer function: point " + std::to_string(i) + " is not finite");
    if (i > 0 && xs[i] < xs[i - 1])
      throw std::invalid_argument("transfer function: point " + std::to_string(i) +
                                  " has decreasing u (" + std::to_string(xs[i]) + " < " +
                                  std::to_string(xs[i - 1]) + ")");
  }
}

/// Index i such that x[i] <= u < x[i+1], for n >= 2 and x[0] <= u < x[n-1].
inline int segment(const double* x, int n, double u) {
  int lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (x[mid] <= u) lo = mid; else hi = mid;
  }
  return lo;
}

template <class V>
V eval_pl(const double* x, const V* v, int n, double u) {
  if (n == 0) return V(0.0);
  if (u <= x[0]) return v[0];
  if (u >= x[n - 1]) return v[n - 1];
  const int i = segment(x, n, u);
  const double w = x[i + 1] - x[i];
  const double t = w > 0.0 ? (u - x[i]) / w : 1.0;
  return v[i] * (1.0 - t) + v[i + 1] * t;
}

}  // namespace

ScalarTF::ScalarTF(const std::vector<double>& xs, const std::vector<double>& vs) {
  check_points(xs, vs.size());
  m_n = static_cast<int>(xs.size());
  for (int i = 0; i < m_n; ++i) {
    if (!std::isfinite(vs[i]))
      throw std::invalid_argument("transfer function: value " + std::to_string(i) + " is not finite");
    m_x[i] = xs[i];
    m_v[i] = vs[i];
  }
}

double ScalarTF::eval(double u) const { return eval_pl(m_x, m_v, m_n, u); }

double ScalarTF::max_over(double u0, double u1) const {
  if (m_n == 0) return 0.0;
  double m = std::fmax(eval(u0), eval(u1));
  for (int i = 0; i < m_n; ++i)
    if (m_x[i] > u0 && m_x[i] < u1) m = std::fmax(m, m_v[i]);
  return m;
}

double ScalarTF::max_value() const {
  double m = 0.0;
  for (int i = 0; i < m_n; ++i) m = std::fmax(m, m_v[i]);
  return m;
}

bool ScalarTF::is_zero() const {
  for (int i = 0; i < m_n; ++i)
    if (m_v[i] != 0.0) return false;
  return true;
}

ColorTF::ColorTF(const std::vector<double>& xs, const std::vector<Color>& vs) {
  check_points(xs, vs.size());
  m_n = static_cast<int>(xs.size());
  for (int i = 0; i < m_n; ++i) {
    if (!is_finite(vs[i]))
      throw std::invalid_argument("transfer function: colour " + std::to_string(i) + " is not finite");
    m_x[i] = xs[i];
    m_v[i] = vs[i];
  }
}

Color ColorTF::eval(double u) const { return eval_pl(m_x, m_v, m_n, u); }

bool ColorTF::is_zero() const {
  for (int i = 0; i < m_n; ++i)
    if (!is_black(m_v[i])) return false;
  return true;
}

}  // namespace tessera
