#include "field/majorant_grid.h"

#include "field/empty_reach.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>

namespace tessera {

void MajorantGrid::build(const FieldView& field, int edge) { set_summary(FieldSummary::build(field, edge)); }

void MajorantGrid::set_summary(std::shared_ptr<const FieldSummary> summary) {
  if (!summary) throw std::invalid_argument("MajorantGrid: null field summary");
  m_summary = std::move(summary);
  m_edge = m_summary->edge();
  for (int a = 0; a < 3; ++a) m_nc[a] = m_summary->cells()[a];
  m_majorant.clear();
  m_reach.clear();
  m_max = 0.0;
}

void MajorantGrid::update(const TransferFunction& tf, double sigma_max) {
  if (!m_summary) throw std::logic_error("MajorantGrid::update before build / set_summary");
  const std::span<const CellRange> ranges = m_summary->ranges();
  m_majorant.resize(ranges.size());
  m_max = 0.0;
  for (std::size_t c = 0; c < ranges.size(); ++c) {
    const CellRange& r = ranges[c];
    // Non-finite vertices enter the interpolation as lo (NaN, -Inf) or hi (+Inf).
    double u0 = 1.0, u1 = 0.0;
    if (r.lo <= r.hi) {
      u0 = tf.normalise(r.lo);
      u1 = tf.normalise(r.hi);
    }
    if (r.nan || r.neg_inf) u0 = 0.0, u1 = std::max(u1, 0.0);
    if (r.pos_inf) u1 = 1.0, u0 = std::min(u0, 1.0);
    double m = 0.0;
    if (u0 <= u1) m = std::min(tf.density_scale * std::max(0.0, tf.opacity.max_over(u0, u1)), sigma_max);
    // A relative margin absorbs rounding in the interpolation weights.
    m_majorant[c] = m > 0.0 ? m * (1.0 + 1e-9) : 0.0;
    m_max = std::max(m_max, m_majorant[c]);
  }
  m_reach.resize(ranges.size());
  fill_empty_reach(m_majorant.data(), m_nc, m_reach.data());
}

}  // namespace tessera
