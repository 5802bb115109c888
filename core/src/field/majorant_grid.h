#pragma once
/// MajorantGrid: macrocells of E^3 voxels over the field, each holding the min/max of the
/// vertex values it touches (its own vertices plus the +1 overlap), and per transfer function
/// the majorant density_scale * max opacity over that value range and how far empty
/// space reaches around each cell (the kernels' walk skips it).
///
/// The ranges come from a FieldSummary (one pass over the field), which the grid shares and
/// never modifies; update (per TF, no pass over the field) derives the majorants from them,
/// so a transfer-function change, or a later prepare of the unchanged field, needs no pass.
#include <tessera/field_summary.h>
#include <tessera/field_view.h>
#include <tessera/transfer_function.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace tessera {

class MajorantGrid {
 public:
  /// Scan the field (a fresh FieldSummary). edge >= 1 voxels; an edge >= every dims-1 gives
  /// a single global cell.
  void build(const FieldView& field, int edge);
  /// Use an existing summary (non-null) instead of scanning. Call update() afterwards.
  void set_summary(std::shared_ptr<const FieldSummary> summary);
  const std::shared_ptr<const FieldSummary>& summary() const { return m_summary; }
  /// Derive the majorant of each cell for tf (1/world unit). Never below the true extinction
  /// of the trilinear field anywhere in the cell, where the kernels clamp extinction to
  /// sigma_max (> 0; Inf for no clamp): a cell's majorant is at most sigma_max (1 + 1e-9).
  void update(const TransferFunction& tf, double sigma_max = INFINITY);

  int edge() const { return m_edge; }
  const std::int64_t* cells() const { return m_nc; }
  std::int64_t cell_index(std::int64_t cx, std::int64_t cy, std::int64_t cz) const {
    return (cz * m_nc[1] + cy) * m_nc[0] + cx;
  }
  const double* majorants() const { return m_majorant.data(); }
  /// Per cell, how far empty space reaches around it (empty_reach.h): 0 for a non-empty cell,
  /// else R >= 1 such that every cell of the grid within R - 1 cells of it along each axis (a
  /// cube of 2R - 1 cells, cut at the grid's faces) is empty. Derived by update() with the
  /// majorants, O(cells).
  const std::uint8_t* empty_reach() const { return m_reach.data(); }
  double max_majorant() const { return m_max; }
  std::uint64_t nan_vertices() const { return m_summary ? m_summary->nan_vertices() : 0; }
  /// Finite min / max over all vertices ({0,0} when none is finite).
  double value_min() const { return m_summary ? m_summary->value_min() : 0.0; }
  double value_max() const { return m_summary ? m_summary->value_max() : 0.0; }

 private:
  std::shared_ptr<const FieldSummary> m_summary;
  int m_edge = 16;  ///< copies of the summary's, read by the kernels
  std::int64_t m_nc[3] = {1, 1, 1};
  std::vector<double> m_majorant;
  std::vector<std::uint8_t> m_reach;
  double m_max = 0.0;
};

}  // namespace tessera
