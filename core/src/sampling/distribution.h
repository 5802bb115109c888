#pragma once
/// Piecewise-constant 1D and 2D distributions for importance sampling (inversion method).
#include <tessera/host_device.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace tessera {

/// f >= 0 on n equal bins of [0,1). sample() returns a continuous x in [0,1) with pdf f/integral.
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(const double* f, std::size_t n) : m_f(f, f + n), m_cdf(n + 1, 0.0) {
    for (std::size_t i = 0; i < n; ++i) m_cdf[i + 1] = m_cdf[i] + m_f[i] / static_cast<double>(n);
    m_integral = m_cdf[n];
    if (m_integral > 0.0)
      for (std::size_t i = 1; i <= n; ++i) m_cdf[i] /= m_integral;
    else
      for (std::size_t i = 1; i <= n; ++i) m_cdf[i] = static_cast<double>(i) / static_cast<double>(n);
  }
  TESSERA_HOST_DEVICE std::size_t size() const { return m_f.size(); }
  TESSERA_HOST_DEVICE double integral() const { return m_integral; }
  /// pdf (w.r.t. x in [0,1)) of bin i.
  TESSERA_HOST_DEVICE double pdf(std::size_t i) const { return m_integral > 0.0 ? m_f[i] / m_integral : 1.0; }
  /// Continuous sample in [0,1); *bin receives the bin index.
  TESSERA_HOST_DEVICE double sample(double u, std::size_t* bin) const {
    const std::size_t n = m_f.size();
    // Last i with cdf[i] <= u.
    std::size_t i = static_cast<std::size_t>(std::upper_bound(m_cdf.begin(), m_cdf.end(), u) - m_cdf.begin());
    i = std::min(n - 1, i > 0 ? i - 1 : 0);
    while (i + 1 < n && m_cdf[i + 1] - m_cdf[i] <= 0.0) ++i;  // never land on an empty bin
    const double width = m_cdf[i + 1] - m_cdf[i];
    double du = width > 0.0 ? (u - m_cdf[i]) / width : 0.5;
    du = std::clamp(du, 0.0, 1.0);
    *bin = i;
    const double x = (static_cast<double>(i) + du) / static_cast<double>(n);
    return std::min(x, 1.0 - 1e-16);
  }

 private:
  std::vector<double> m_f;
  std::vector<double> m_cdf;
  double m_integral = 0.0;
};

/// f(x, y) >= 0 on nx by ny bins of [0,1)^2, rows indexed by y.
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<double>& f, std::size_t nx, std::size_t ny) {
    std::vector<double> marginal(ny);
    m_rows.reserve(ny);
    for (std::size_t y = 0; y < ny; ++y) {
      m_rows.emplace_back(&f[y * nx], nx);
      marginal[y] = m_rows.back().integral();
    }
    m_marginal = Distribution1D(marginal.data(), ny);
  }
  /// Sample (x, y) in [0,1)^2; returns the pdf w.r.t. area in [0,1)^2.
  TESSERA_HOST_DEVICE double sample(double u1, double u2, double* x, double* y) const {
    std::size_t by = 0, bx = 0;
    *y = m_marginal.sample(u2, &by);
    *x = m_rows[by].sample(u1, &bx);
    return m_marginal.pdf(by) * m_rows[by].pdf(bx);
  }
  TESSERA_HOST_DEVICE double pdf(double x, double y) const {
    const std::size_t ny = m_rows.size(), nx = m_rows.empty() ? 0 : m_rows[0].size();
    const std::size_t bx = std::min(nx - 1, static_cast<std::size_t>(x * nx));
    const std::size_t by = std::min(ny - 1, static_cast<std::size_t>(y * ny));
    if (m_marginal.integral() <= 0.0) return 1.0;
    return m_marginal.pdf(by) * (m_rows[by].integral() > 0.0 ? m_rows[by].pdf(bx) : 0.0);
  }
  TESSERA_HOST_DEVICE double integral() const { return m_marginal.integral(); }

 private:
  std::vector<Distribution1D> m_rows;
  Distribution1D m_marginal;
};

}  // namespace tessera
