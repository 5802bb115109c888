#include "majorant_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tessera {
namespace {

std::int64_t cells_along(std::int64_t dims, int edge) {
  return std::max<std::int64_t>(1, (dims - 1 + edge - 1) / edge);
}

}  // namespace

void MajorantGrid::build(const FieldView& field, int edge) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1");
  m_edge = edge;
  for (int a = 0; a < 3; ++a) m_nc[a] = cells_along(field.dims[a], edge);
  const std::int64_t ncell = m_nc[0] * m_nc[1] * m_nc[2];
  const double inf = std::numeric_limits<double>::infinity();
  m_range.assign(ncell, CellRange{inf, -inf, false, false, false});
  m_nan = 0;
  double vmin = inf, vmax = -inf;

  dispatch_dtype(field, [&](auto view) {
    const std::int64_t nx = field.dims[0], ny = field.dims[1], nz = field.dims[2];
    for (std::int64_t k = 0; k < nz; ++k)
      for (std::int64_t j = 0; j < ny; ++j)
        for (std::int64_t i = 0; i < nx; ++i) {
          const double v = view.load(i, j, k);
          // A vertex on a cell boundary belongs to both neighbours (+1 overlap).
          const std::int64_t ci0 = std::min(std::max<std::int64_t>(0, (i - 1) / edge), m_nc[0] - 1);
          const std::int64_t ci1 = std::min(i / edge, m_nc[0] - 1);
          const std::int64_t cj0 = std::min(std::max<std::int64_t>(0, (j - 1) / edge), m_nc[1] - 1);
          const std::int64_t cj1 = std::min(j / edge, m_nc[1] - 1);
          const std::int64_t ck0 = std::min(std::max<std::int64_t>(0, (k - 1) / edge), m_nc[2] - 1);
          const std::int64_t ck1 = std::min(k / edge, m_nc[2] - 1);
          const bool nan = std::isnan(v), pinf = v == inf, ninf = v == -inf;
          if (nan) ++m_nan;
          if (std::isfinite(v)) {
            vmin = std::min(vmin, v);
            vmax = std::max(vmax, v);
          }
          for (std::int64_t ck = ck0; ck <= ck1; ++ck)
            for (std::int64_t cj = cj0; cj <= cj1; ++cj)
              for (std::int64_t ci = ci0; ci <= ci1; ++ci) {
                CellRange& r = m_range[cell_index(ci, cj, ck)];
                if (nan) r.nan = true;
                else if (pinf) r.pos_inf = true;
                else if (ninf) r.neg_inf = true;
                else {
                  r.lo = std::min(r.lo, v);
                  r.hi = std::max(r.hi, v);
                }
              }
        }
  });
  if (vmin > vmax) vmin = vmax = 0.0;
  m_vmin = vmin;
  m_vmax = vmax;
}

void MajorantGrid::update(const TransferFunction& tf) {
  m_majorant.resize(m_range.size());
  m_max = 0.0;
  for (std::size_t c = 0; c < m_range.size(); ++c) {
    const CellRange& r = m_range[c];
    // Non-finite vertices enter the interpolation as lo (NaN, -Inf) or hi (+Inf).
    double u0 = 1.0, u1 = 0.0;
    if (r.lo <= r.hi) {
      u0 = tf.normalise(r.lo);
      u1 = tf.normalise(r.hi);
    }
    if (r.nan || r.neg_inf) u0 = 0.0, u1 = std::max(u1, 0.0);
    if (r.pos_inf) u1 = 1.0, u0 = std::min(u0, 1.0);
    double m = 0.0;
    if (u0 <= u1) m = tf.density_scale * std::max(0.0, tf.opacity.max_over(u0, u1));
    // A relative margin absorbs rounding in the interpolation weights.
    m_majorant[c] = m > 0.0 ? m * (1.0 + 1e-9) : 0.0;
    m_max = std::max(m_max, m_majorant[c]);
  }
}

}  // namespace tessera
