#pragma once
/// Shared helpers for the core tests: small scenes, image statistics and the chi-square
/// critical value used by the statistical tests. Header-only; test code only.
#include <tessera/film.h>
#include <tessera/render.h>
#include <tessera/scene.h>

#include <catch2/catch.hpp>

#include "field/majorant_grid.h"
#include "kernel/grid_medium.h"
#include "sampling/rng.h"

#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace tessera_test {

/// Mean over all pixels of the pixel means of one film channel, and its standard error
/// estimated from each pixel's sample variance (pixels are independent; every pixel has
/// the same sample count, so the image mean is the plain mean of the pixel means).
struct MeanWithError {
  double mean = 0.0;
  double se = 0.0;  ///< standard error of `mean`
  std::uint64_t samples = 0;
  /// |mean - expected| / se, with se floored so that a zero-variance estimate may differ from
  /// the expectation only by rounding.
  double z(double expected) const {
    return std::fabs(mean - expected) / std::fmax(se, 1e-9 * std::fmax(1.0, std::fabs(expected)));
  }
};

/// Luminance statistics of the film (luminance == each channel for grey radiance).
inline MeanWithError luminance_stats(const tessera::Film& film) {
  MeanWithError r;
  double var_sum = 0.0;
  const auto& px = film.pixels();
  for (const tessera::PixelSums& p : px) {
    const double n = static_cast<double>(p.n);
    const double m = p.lum / n;
    r.mean += m;
    r.samples += p.n;
    if (p.n > 1) var_sum += std::fmax(0.0, (p.lum2 - p.lum * m) / (n - 1.0)) / n;
  }
  const double npx = static_cast<double>(px.size());
  r.mean /= npx;
  r.se = std::sqrt(var_sum) / npx;
  return r;
}

/// Mean over pixels of the red channel (the film keeps no red variance).
inline double mean_red(const tessera::Film& film) {
  double s = 0.0;
  for (const tessera::PixelSums& p : film.pixels()) s += p.r / static_cast<double>(p.n);
  return s / static_cast<double>(film.pixels().size());
}

inline double mean_alpha(const tessera::Film& film) {
  double s = 0.0;
  for (const tessera::PixelSums& p : film.pixels()) s += p.a / static_cast<double>(p.n);
  return s / static_cast<double>(film.pixels().size());
}

/// Render a prepared scene into a fresh film.
inline tessera::Film render_film(const tessera::PreparedScene& ps, tessera::RenderStats* stats = nullptr) {
  tessera::Film film(ps.desc().image.width, ps.desc().image.height);
  tessera::RenderStats st;
  tessera::render(ps, film, st);
  if (stats) *stats = st;
  return film;
}

/// Upper critical value of the chi-square distribution with k degrees of freedom at
/// upper-tail probability alpha, by the Wilson-Hilferty approximation (relative error well
/// under 1% for k >= 10). z is the standard normal upper quantile of alpha.
inline double chi2_critical(int k, double z_alpha) {
  const double a = 2.0 / (9.0 * k);
  const double c = 1.0 - a + z_alpha * std::sqrt(a);
  return k * c * c * c;
}
/// Standard normal upper quantile of 1e-4 (one-sided).
inline constexpr double kZ1e4 = 3.719016485;

/// Pearson's chi-square statistic of observed counts against expected probabilities, merging
/// bins whose expected count is under 5 into their neighbour. Returns the statistic and sets
/// *dof to (bins used - 1).
inline double chi_square(const std::vector<double>& observed, const std::vector<double>& prob, double total, int* dof) {
  std::vector<double> o_bins, e_bins;
  double o_acc = 0.0, e_acc = 0.0;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    o_acc += observed[i];
    e_acc += prob[i] * total;
    if (e_acc >= 5.0) {
      o_bins.push_back(o_acc);
      e_bins.push_back(e_acc);
      o_acc = e_acc = 0.0;
    }
  }
  if (o_acc > 0.0 || e_acc > 0.0) {  // leftover tail: fold into the last bin
    if (e_bins.empty()) {
      o_bins.push_back(o_acc);
      e_bins.push_back(e_acc);
    } else {
      o_bins.back() += o_acc;
      e_bins.back() += e_acc;
    }
  }
  double chi2 = 0.0;
  for (std::size_t i = 0; i < o_bins.size(); ++i)
    chi2 += e_bins[i] > 0.0 ? (o_bins[i] - e_bins[i]) * (o_bins[i] - e_bins[i]) / e_bins[i]
                            : (o_bins[i] > 0.0 ? 1e300 : 0.0);
  *dof = static_cast<int>(o_bins.size()) - 1;
  return chi2;
}

/// The kernels' medium over a view, as render.cpp builds it; without a grid it has one cell
/// and no majorant table (enough for value(), sigma_t() and gradients).
template <class T>
tessera::GridMedium<T> make_medium(const tessera::FieldView& f, const tessera::TransferFunction& tf,
                                   const tessera::MajorantGrid* grid = nullptr) {
  tessera::GridMedium<T> m{};
  m.field = tessera::typed<T>(f);
  for (int a = 0; a < 3; ++a) {
    m.n[a] = f.dims[a];
    m.hi_index[a] = static_cast<double>(f.dims[a] - 1);
    m.nc[a] = grid ? grid->cells()[a] : 1;
  }
  m.tf = &tf;
  m.majorant = grid ? grid->majorants() : nullptr;
  m.empty_reach = grid ? grid->empty_reach() : nullptr;
  m.cell_edge = grid ? grid->edge() : 1.0;
  return m;
}

template <class T>
constexpr tessera::DType dtype_of() {
  if constexpr (std::is_same_v<T, std::uint8_t>) return tessera::DType::UInt8;
  else if constexpr (std::is_same_v<T, std::int16_t>) return tessera::DType::Int16;
  else if constexpr (std::is_same_v<T, std::uint16_t>) return tessera::DType::UInt16;
  else if constexpr (std::is_same_v<T, float>) return tessera::DType::Float32;
  else return tessera::DType::Float64;
}

/// Constant-value float field of n^3 vertices.
inline std::vector<float> constant_field(int nx, int ny, int nz, float v) {
  return std::vector<float>(static_cast<std::size_t>(nx) * ny * nz, v);
}

/// A smooth heterogeneous field in [0, 1] with some structure (blobs and a shell), C order
/// (i fastest), used by the determinism and robustness tests.
inline std::vector<float> blobby_field(int nx, int ny, int nz) {
  std::vector<float> f(static_cast<std::size_t>(nx) * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x = (i + 0.5) / nx - 0.5, y = (j + 0.5) / ny - 0.5, z = (k + 0.5) / nz - 0.5;
        const double r = std::sqrt(x * x + y * y + z * z);
        const double shell = std::exp(-std::pow((r - 0.3) / 0.06, 2.0));
        const double blob = std::exp(-((x - 0.1) * (x - 0.1) + (y + 0.1) * (y + 0.1) + z * z) / 0.01);
        const double ripple = 0.15 * (1.0 + std::sin(17.0 * x) * std::cos(13.0 * y + 5.0 * z));
        f[(static_cast<std::size_t>(k) * ny + j) * nx + i] =
            static_cast<float>(std::fmin(1.0, shell + blob + 0.3 * ripple));
      }
  return f;
}

/// Random rays through the medium's box (faces and outer half cells included), in p space:
/// every segment the macrocell walk reports bounds sigma_t at its ends and inside, and the
/// walk covers the whole ray. Counts violations into bad.
template <class M>
inline void walk_rays(const M& m, bool cell, tessera::Rng& rng, int& bad, int& segments) {
  CHECK(m.outer_half == cell);
  for (int r = 0; r < 200; ++r) {
    // Rays between random points of the box (faces and outer half cells included), in p
    tessera::Vec3 pa, pb;
    for (int a = 0; a < 3; ++a) {
      const double lo = m.box_lo[a], hi = m.box_hi[a];
      pa[a] = lo + (hi - lo) * (r % 7 == 0 ? std::round(rng.uniform()) : rng.uniform());
      pb[a] = lo + (hi - lo) * rng.uniform();
    }
    const double len = glm::length(pb - pa);
    if (!(len > 1e-9)) continue;
    const tessera::Vec3 dv = (pb - pa) / len;
    double covered = 0.0;
    tessera::traverse_macrocells(m, pa, dv, 0.0, len, [&](double ta, double tb, double maj) {
      ++segments;
      covered += tb - ta;
      for (int k = 0; k < 6; ++k) {
        const double t = k == 0 ? ta : (k == 1 ? tb : ta + (tb - ta) * rng.uniform());
        if (!(m.sigma_t(pa + t * dv) <= maj)) ++bad;
      }
      return false;
    });
    // The walk covers the whole segment (the outer half cells included)
    if (!(std::fabs(covered - len) <= 1e-9 * (1.0 + len))) ++bad;
  }
}

}  // namespace tessera_test
