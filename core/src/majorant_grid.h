#pragma once
/// MajorantGrid: macrocells of E^3 voxels over the field, each holding the min/max of the
/// vertex values it touches (its own vertices plus the +1 overlap), and per transfer function
/// the majorant density_scale * max opacity over that value range.
///
/// Build (one pass over the field) and update (per TF, no pass over the field) are separate,
/// so a transfer-function change re-derives majorants from the stored ranges alone.
#include <tessera/field_view.h>
#include <tessera/transfer_function.h>

#include <cstdint>
#include <vector>

namespace tessera {

class MajorantGrid {
 public:
  /// Scan the field. edge >= 1 voxels; an edge >= every dims-1 gives a single global cell.
  void build(const FieldView& field, int edge);
  /// Derive the majorant of each cell for tf (1/world unit). Never below the true extinction
  /// of the trilinear field anywhere in the cell.
  void update(const TransferFunction& tf);

  int edge() const { return m_edge; }
  const std::int64_t* cells() const { return m_nc; }
  std::int64_t cell_index(std::int64_t cx, std::int64_t cy, std::int64_t cz) const {
    return (cz * m_nc[1] + cy) * m_nc[0] + cx;
  }
  const double* majorants() const { return m_majorant.data(); }
  double max_majorant() const { return m_max; }
  std::uint64_t nan_vertices() const { return m_nan; }
  /// Finite min / max over all vertices ({0,0} when none is finite).
  double value_min() const { return m_vmin; }
  double value_max() const { return m_vmax; }

 private:
  struct CellRange {
    double lo, hi;            ///< finite range (lo > hi when the cell has no finite vertex)
    bool nan, pos_inf, neg_inf;
  };
  int m_edge = 16;
  std::int64_t m_nc[3] = {1, 1, 1};
  std::vector<CellRange> m_range;
  std::vector<double> m_majorant;
  double m_max = 0.0;
  double m_vmin = 0.0, m_vmax = 0.0;
  std::uint64_t m_nan = 0;
};

}  // namespace tessera
