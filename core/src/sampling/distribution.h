#pragma once
/// Piecewise-constant 1D and 2D distributions for importance sampling (inversion method).
/// The owning classes (Distribution1D, Distribution2D) build their tables on the host in one
/// flat array each; sampling reads them through views (Distribution1DView,
/// Distribution2DView: pointers and sizes, trivially copyable), which are host and device
/// code, so a table copied to a GPU is sampled by the same code through a view of the copy.
#include <tessera/host_device.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace tessera {

/// f[0..n) >= 0 on n equal bins of [0,1) and its normalised cdf[0..n], over tables held
/// elsewhere. sample() returns a continuous x in [0,1) with pdf f/integral.
struct Distribution1DView {
  const double* f = nullptr;
  const double* cdf = nullptr;
  std::size_t n = 0;
  double integral = 0.0;

  /// pdf (w.r.t. x in [0,1)) of bin i.
  TESSERA_HOST_DEVICE double pdf(std::size_t i) const { return integral > 0.0 ? f[i] / integral : 1.0; }
  /// Continuous sample in [0,1); *bin receives the bin index.
  TESSERA_HOST_DEVICE double sample(double u, std::size_t* bin) const {
    // Last i with cdf[i] <= u, from the first of cdf[0..n] above u (std::upper_bound's
    // answer, written out: the library's algorithm compiled for the device picked other bins
    // on an H200, tests/gpu/test_gpu_environment.cpp)
    std::size_t lo = 0, hi = n + 1;
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (u < cdf[mid]) hi = mid;
      else lo = mid + 1;
    }
    std::size_t i = std::min(n - 1, lo > 0 ? lo - 1 : 0);
    while (i + 1 < n && cdf[i + 1] - cdf[i] <= 0.0) ++i;  // never land on an empty bin
    const double width = cdf[i + 1] - cdf[i];
    double du = width > 0.0 ? (u - cdf[i]) / width : 0.5;
    du = std::clamp(du, 0.0, 1.0);
    *bin = i;
    const double x = (static_cast<double>(i) + du) / static_cast<double>(n);
    return std::min(x, 1.0 - 1e-16);
  }
};

namespace detail {
/// Writes f's n values, its normalised cdf (n + 1) and its integral at out[0 .. 2n + 2).
inline double build_distribution(const double* f, std::size_t n, double* out) {
  double* cdf = out + n;
  std::copy(f, f + n, out);
  cdf[0] = 0.0;
  for (std::size_t i = 0; i < n; ++i) cdf[i + 1] = cdf[i] + f[i] / static_cast<double>(n);
  const double integral = cdf[n];
  if (integral > 0.0)
    for (std::size_t i = 1; i <= n; ++i) cdf[i] /= integral;
  else
    for (std::size_t i = 1; i <= n; ++i) cdf[i] = static_cast<double>(i) / static_cast<double>(n);
  out[2 * n + 1] = integral;
  return integral;
}
/// The view of a table written by build_distribution.
TESSERA_HOST_DEVICE inline Distribution1DView distribution_at(const double* t, std::size_t n) {
  return {t, t + n, n, t[2 * n + 1]};
}
}  // namespace detail

/// Owns a 1D distribution's table (f, cdf, integral: 2n + 2 doubles).
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(const double* f, std::size_t n) : m_t(2 * n + 2), m_n(n) {
    detail::build_distribution(f, n, m_t.data());
  }
  Distribution1DView view() const { return m_n ? detail::distribution_at(m_t.data(), m_n) : Distribution1DView{}; }
  std::size_t size() const { return m_n; }
  double integral() const { return view().integral; }
  double pdf(std::size_t i) const { return view().pdf(i); }
  double sample(double u, std::size_t* bin) const { return view().sample(u, bin); }

 private:
  std::vector<double> m_t;
  std::size_t m_n = 0;
};

/// f(x, y) >= 0 on nx by ny bins of [0,1)^2 over a table held elsewhere (Distribution2D's
/// layout): ny rows of 2 nx + 2 doubles (row y's 1D table), then the marginal's 2 ny + 2.
struct Distribution2DView {
  const double* t = nullptr;
  std::size_t nx = 0, ny = 0;

  TESSERA_HOST_DEVICE Distribution1DView row(std::size_t y) const {
    return detail::distribution_at(t + y * (2 * nx + 2), nx);
  }
  TESSERA_HOST_DEVICE Distribution1DView marginal() const { return detail::distribution_at(t + ny * (2 * nx + 2), ny); }
  /// Sample (x, y) in [0,1)^2; returns the pdf w.r.t. area in [0,1)^2.
  TESSERA_HOST_DEVICE double sample(double u1, double u2, double* x, double* y) const {
    std::size_t by = 0, bx = 0;
    const Distribution1DView m = marginal();
    *y = m.sample(u2, &by);
    const Distribution1DView r = row(by);
    *x = r.sample(u1, &bx);
    return m.pdf(by) * r.pdf(bx);
  }
  TESSERA_HOST_DEVICE double pdf(double x, double y) const {
    if (nx == 0 || ny == 0) return 1.0;
    const std::size_t bx = std::min(nx - 1, static_cast<std::size_t>(x * nx));
    const std::size_t by = std::min(ny - 1, static_cast<std::size_t>(y * ny));
    const Distribution1DView m = marginal();
    if (m.integral <= 0.0) return 1.0;
    const Distribution1DView r = row(by);
    return m.pdf(by) * (r.integral > 0.0 ? r.pdf(bx) : 0.0);
  }
  TESSERA_HOST_DEVICE double integral() const { return ny ? marginal().integral : 0.0; }
};

/// Owns a 2D distribution's table: f(x, y) = f[y nx + x], rows indexed by y.
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<double>& f, std::size_t nx, std::size_t ny)
      : m_t(ny * (2 * nx + 2) + 2 * ny + 2), m_nx(nx), m_ny(ny) {
    std::vector<double> marginal(ny);
    for (std::size_t y = 0; y < ny; ++y)
      marginal[y] = detail::build_distribution(&f[y * nx], nx, &m_t[y * (2 * nx + 2)]);
    detail::build_distribution(marginal.data(), ny, &m_t[ny * (2 * nx + 2)]);
  }
  /// A view of this table (valid while this object lives and is not assigned to).
  Distribution2DView view() const { return m_ny ? Distribution2DView{m_t.data(), m_nx, m_ny} : Distribution2DView{}; }
  /// The table, for a copy elsewhere (a GPU's): view it with Distribution2DView{copy, nx, ny}.
  const std::vector<double>& table() const { return m_t; }
  double sample(double u1, double u2, double* x, double* y) const { return view().sample(u1, u2, x, y); }
  double pdf(double x, double y) const { return view().pdf(x, y); }
  double integral() const { return view().integral(); }

 private:
  std::vector<double> m_t;
  std::size_t m_nx = 0, m_ny = 0;
};

}  // namespace tessera
