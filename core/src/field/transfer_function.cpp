#include <tessera/transfer_function.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace tessera {
namespace {

void check_points(const std::vector<double>& xs, std::size_t nv) {
  if (xs.size() != nv) throw std::invalid_argument("transfer function: x and value counts differ");
  if (xs.size() > static_cast<std::size_t>(kMaxTfPoints))
    throw std::invalid_argument("transfer function: " + std::to_string(xs.size()) + " points, at most " +
                                std::to_string(kMaxTfPoints) + " allowed");
  for (std::size_t i = 0; i < xs.size(); ++i) {
    if (!std::isfinite(xs[i]))
      throw std::invalid_argument("transfer function: point " + std::to_string(i) + " is not finite");
    if (i > 0 && xs[i] < xs[i - 1])
      throw std::invalid_argument("transfer function: point " + std::to_string(i) + " has decreasing u (" +
                                  std::to_string(xs[i]) + " < " + std::to_string(xs[i - 1]) + ")");
  }
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
  // Segment table: for each bin start, the segment i with x[i] <= u < x[i+1] (clamped into
  // [x[0], x[n-1]); a bin start past the last point is never looked up)
  for (int b = 0; b < kTfBins; ++b) {
    const double u = static_cast<double>(b) / kTfBins;
    int i = 0;
    if (m_n >= 2 && u > m_x[0]) {
      if (u >= m_x[m_n - 1]) i = m_n - 2;
      else i = detail::tf_segment(m_x, m_n, u);
    }
    m_seg[b] = static_cast<std::uint8_t>(i);
  }
}

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

bool ColorTF::is_zero() const {
  for (int i = 0; i < m_n; ++i)
    if (!is_black(m_v[i])) return false;
  return true;
}

}  // namespace tessera
