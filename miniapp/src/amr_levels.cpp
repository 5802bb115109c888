// tessera-heat --amr: the refined levels (amr_levels.h).
#include "amr_levels.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace heat {
namespace {

/// Where a level's element i sits along one axis, and the level-0 samples that interpolate it.
struct AxisSample {
  std::int64_t i0 = 0;  ///< lower level-0 vertex of the stencil (global), in [0, N - 2]
  double frac = 0.0;    ///< weight of i0 + 1
  double x = 0.0;       ///< position, unit-cube coordinates
};

AxisSample axis_sample(std::int64_t i, std::int64_t R, bool cell, std::int64_t N, double h) {
  // Level-0 vertex-index position, clamped to the outer samples as the renderer clamps
  double u = cell ? (static_cast<double>(i) + 0.5) / static_cast<double>(R) - 0.5
                  : static_cast<double>(i) / static_cast<double>(R);
  u = std::clamp(u, 0.0, static_cast<double>(N - 1));
  AxisSample s;
  s.i0 = std::min<std::int64_t>(static_cast<std::int64_t>(std::floor(u)), N - 2);
  s.frac = u - static_cast<double>(s.i0);
  s.x = u * h;
  return s;
}

double lerp(double a, double b, double t) { return a + t * (b - a); }

/// Trilinear interpolation in a C-order array (strides sy, sz) from element c.
double trilinear(const double* v, std::size_t c, std::size_t sy, std::size_t sz, double fx, double fy, double fz) {
  const double x00 = lerp(v[c], v[c + 1], fx), x10 = lerp(v[c + sy], v[c + sy + 1], fx);
  const double x01 = lerp(v[c + sz], v[c + sz + 1], fx), x11 = lerp(v[c + sz + sy], v[c + sz + sy + 1], fx);
  return lerp(lerp(x00, x10, fy), lerp(x01, x11, fy), fz);
}

}  // namespace

std::vector<AmrBox> refined_boxes(const Index3& global, const std::array<double, 3>& h, bool cell,
                                  const std::array<double, 3>& centre, const std::vector<double>& half_width) {
  std::vector<AmrBox> boxes;
  for (std::size_t l = 0; l < half_width.size(); ++l) {
    AmrBox b;
    for (int a = 0; a < 3; ++a) {
      // Level-0 extent: vertices 0 .. N-1 (vertex data) or cells 0 .. N (cell data, whose
      // cell i spans [(i - 0.5) h, (i + 0.5) h] around vertex i)
      const std::int64_t top = cell ? global[a] : global[a] - 1;
      const double shift = cell ? 0.5 : 0.0;
      std::int64_t lo = static_cast<std::int64_t>(std::floor((centre[a] - half_width[l]) / h[a] + shift));
      std::int64_t hi = static_cast<std::int64_t>(std::ceil((centre[a] + half_width[l]) / h[a] + shift));
      const std::int64_t floor_lo = l == 0 ? 0 : boxes.back().lo[a];
      const std::int64_t ceil_hi = l == 0 ? top : boxes.back().hi[a];
      lo = std::clamp(lo, floor_lo, ceil_hi - 1);
      hi = std::clamp(hi, lo + 1, ceil_hi);
      b.lo[a] = lo;
      b.hi[a] = hi;
    }
    boxes.push_back(b);
  }
  return boxes;
}

void rank_share(const AmrBox& box, std::int64_t R, bool cell, const Index3& offset, const Index3& owned,
                Index3& share_offset, Index3& share_dims) {
  for (int a = 0; a < 3; ++a) {
    // Level-l elements of the box: [lo R, hi R] (vertices) or [lo R, hi R) (cells); the rank's:
    // those whose level-0 position floor(i / R) lies in its block
    const std::int64_t first = std::max(box.lo[a] * R, offset[a] * R);
    const std::int64_t last = std::min(cell ? box.hi[a] * R - 1 : box.hi[a] * R, (offset[a] + owned[a]) * R - 1);
    share_offset[a] = first;
    share_dims[a] = last - first + 1;
  }
}

AmrLevels::AmrLevels(const CartDecomposition& decomp, const HeatParams& params, const AmrSettings& settings,
                     HeatSource followed)
    : m_decomp(decomp), m_params(params), m_settings(settings), m_followed(followed) {
  if (settings.levels < 2 || settings.levels > 3)
    throw std::invalid_argument("--levels " + std::to_string(settings.levels) + ": 2 or 3 levels are allowed");
  if (settings.ratio != 2 && settings.ratio != 4)
    throw std::invalid_argument("--ratio " + std::to_string(settings.ratio) + ": the ratio must be 2 or 4");
}

void AmrLevels::update(const HeatSolver& solver) {
  // Re-grid around the followed source
  std::vector<double> half_width;
  for (int l = 1; l < m_settings.levels; ++l)
    half_width.push_back(m_settings.half_width_sigmas[static_cast<std::size_t>(l - 1)] * m_followed.sigma);
  m_boxes = refined_boxes(m_decomp.global_dims(), solver.spacing(), m_settings.cell,
                          source_centre(m_followed, solver.time()), half_width);

  // This rank's share of each level, filled from level 0
  std::vector<AmrPatch> patches;
  std::int64_t R = 1;
  for (int l = 1; l < m_settings.levels; ++l) {
    R *= m_settings.ratio;
    AmrPatch p;
    p.level = l;
    rank_share(m_boxes[static_cast<std::size_t>(l - 1)], R, m_settings.cell, m_decomp.offset(), m_decomp.owned(),
               p.offset, p.dims);
    if (p.dims[0] <= 0 || p.dims[1] <= 0 || p.dims[2] <= 0) continue;
    // (reuse last step's storage of the same level)
    for (AmrPatch& old : m_patches)
      if (old.level == l) p.values.swap(old.values);
    fill(solver, p);
    patches.push_back(std::move(p));
  }
  m_patches.swap(patches);
}

void AmrLevels::fill(const HeatSolver& solver, AmrPatch& p) const {
  const Index3& N = m_decomp.global_dims();
  const Index3& off = m_decomp.offset();
  const Index3& adims = solver.array_dims();
  const std::array<double, 3>& h = solver.spacing();
  std::int64_t R = 1;
  for (int l = 0; l < p.level; ++l) R *= m_settings.ratio;

  // Per axis: each element's stencil and position, and the level-0 range the stencils touch
  std::array<std::vector<AxisSample>, 3> axis;
  Index3 cmin{}, cmax{};
  for (int a = 0; a < 3; ++a) {
    for (std::int64_t i = 0; i < p.dims[a]; ++i)
      axis[a].push_back(axis_sample(p.offset[a] + i, R, m_settings.cell, N[a], h[a]));
    cmin[a] = axis[a].front().i0;
    cmax[a] = axis[a].back().i0 + 1;
    if (cmin[a] - off[a] + 1 < 0 || cmax[a] - off[a] + 1 >= adims[a])
      throw std::logic_error("AMR patch reads outside the rank's array (a bug)");
  }

  // The sources' steady excess at the level-0 vertices of that range
  const double t = solver.time();
  const std::int64_t ux = cmax[0] - cmin[0] + 1, uy = cmax[1] - cmin[1] + 1, uz = cmax[2] - cmin[2] + 1;
  std::vector<double> U0(static_cast<std::size_t>(ux * uy * uz));
  const auto excess = [&](const std::array<double, 3>& x) {
    double u = 0.0;
    for (const HeatSource& s : m_params.sources) u += steady_excess(s, t, m_params.alpha, x);
    return u;
  };
  for (std::int64_t k = 0; k < uz; ++k)
    for (std::int64_t j = 0; j < uy; ++j)
      for (std::int64_t i = 0; i < ux; ++i)
        U0[static_cast<std::size_t>((k * uy + j) * ux + i)] =
            excess({static_cast<double>(cmin[0] + i) * h[0], static_cast<double>(cmin[1] + j) * h[1],
                    static_cast<double>(cmin[2] + k) * h[2]});

  // f = I_0[T] + (u - I_0[u]) at every element
  const double* T = solver.data();
  const std::size_t tsy = static_cast<std::size_t>(adims[0]), tsz = static_cast<std::size_t>(adims[0] * adims[1]);
  const std::size_t usy = static_cast<std::size_t>(ux), usz = static_cast<std::size_t>(ux * uy);
  p.values.resize(static_cast<std::size_t>(p.dims[0] * p.dims[1] * p.dims[2]));
  std::size_t out = 0;
  for (const AxisSample& sz : axis[2])
    for (const AxisSample& sy : axis[1])
      for (const AxisSample& sx : axis[0]) {
        const std::size_t tc = static_cast<std::size_t>(
            ((sz.i0 - off[2] + 1) * adims[1] + (sy.i0 - off[1] + 1)) * adims[0] + (sx.i0 - off[0] + 1));
        const std::size_t uc =
            static_cast<std::size_t>(((sz.i0 - cmin[2]) * uy + (sy.i0 - cmin[1])) * ux + (sx.i0 - cmin[0]));
        const double coarse = trilinear(T, tc, tsy, tsz, sx.frac, sy.frac, sz.frac);
        const double detail =
            excess({sx.x, sy.x, sz.x}) - trilinear(U0.data(), uc, usy, usz, sx.frac, sy.frac, sz.frac);
        p.values[out++] = coarse + detail;
      }
}

}  // namespace heat
