#include "majorant_grid.h"

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
  m_max = 0.0;
}

void MajorantGrid::update(const TransferFunction& tf) {
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
    if (u0 <= u1) m = tf.density_scale * std::max(0.0, tf.opacity.max_over(u0, u1));
    // A relative margin absorbs rounding in the interpolation weights.
    m_majorant[c] = m > 0.0 ? m * (1.0 + 1e-9) : 0.0;
    m_max = std::max(m_max, m_majorant[c]);
  }
  // The coarse level: max over each block of ratio^3 macrocells.
  m_ratio = m_edge < kCoarseEdge ? (kCoarseEdge + m_edge - 1) / m_edge : 1;
  for (int a = 0; a < 3; ++a) m_ncc[a] = (m_nc[a] + m_ratio - 1) / m_ratio;
  if (m_ratio > 1 && m_ncc[0] * m_ncc[1] * m_ncc[2] == 1) m_ratio = 1;  // one coarse cell: useless
  m_coarse.assign(m_ratio > 1 ? static_cast<std::size_t>(m_ncc[0] * m_ncc[1] * m_ncc[2]) : 0, 0.0);
  if (m_ratio > 1) {
    for (std::int64_t k = 0; k < m_nc[2]; ++k)
      for (std::int64_t j = 0; j < m_nc[1]; ++j)
        for (std::int64_t i = 0; i < m_nc[0]; ++i) {
          double& c = m_coarse[static_cast<std::size_t>(((k / m_ratio) * m_ncc[1] + j / m_ratio) * m_ncc[0] + i / m_ratio)];
          c = std::max(c, m_majorant[static_cast<std::size_t>(cell_index(i, j, k))]);
        }
  }
}

}  // namespace tessera
