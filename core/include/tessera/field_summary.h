#pragma once
/// FieldSummary: what one pass over a field's values yields, kept so that later prepares of
/// the same, unchanged field need no pass at all (prepare(field, scene, reuse), render.h).
///
/// For one macrocell edge E it holds, per macrocell of E^3 voxels, the range of the vertex
/// values the cell touches (its own vertices plus the +1 overlap: cell c along an axis covers
/// vertices c*E ..= min((c+1)*E, n-1)): the finite min and max and whether a NaN, +Inf or -Inf
/// vertex is among them. Over the whole field: the NaN vertex count and the finite min / max.
/// An edge >= every dims-1 gives a single cell (the global majorant).
///
/// It also records the layout it was read from (data pointer, dtype, dims, byte strides).
/// `matches()` compares layouts only: it cannot see whether the values at that memory have
/// changed. Reusing a summary is the caller's promise that they have not; a summary of
/// changed values gives majorants that may be too low, i.e. a biased image, not a crash.
///
/// Immutable once built; safe to share between threads and prepares (std::shared_ptr<const>).
/// It holds no pointer that is ever dereferenced after the build: the recorded data pointer
/// is only compared.
#include <tessera/field_view.h>
#include <tessera/integrator.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace tessera {

/// The layout of a FieldView, compared (never dereferenced) to decide reuse.
struct FieldLayout {
  const void* data = nullptr;
  DType dtype = DType::Float32;
  std::int64_t dims[3] = {0, 0, 0};
  std::int64_t byte_strides[3] = {0, 0, 0};

  static FieldLayout of(const FieldView& field);
  bool operator==(const FieldLayout& o) const;
};

/// Value range of the vertices one macrocell touches. Zeros are recorded as +0.0 (a -0.0
/// vertex gives lo or hi +0.0), so that ranges combined in any order are bit-identical.
struct CellRange {
  double lo, hi;  ///< finite min / max (lo > hi when the cell has no finite vertex)
  bool nan, pos_inf, neg_inf;
};

/// The macrocell edge prepare() uses for `integrator` on `field`: `macrocell`, or for the
/// global majorant an edge that makes one cell.
int majorant_edge(const FieldView& field, const IntegratorDesc& integrator);

class FieldSummary {
 public:
  /// Scans `field` (one pass, TBB-parallel over slabs of cells). edge >= 1, else throws
  /// std::invalid_argument. The result is bit-identical for any thread count: within every
  /// cell, values are combined in the field's (k, j, i) order, and counts are integer sums.
  /// The field must be valid (FieldView::validate) and must not change during the build.
  FieldSummary(const FieldView& field, int edge);

  /// The parts of a summary that ranks combine in distributed mode: per global cell the
  /// finite min (lo), max (hi) and flags (bit 0 NaN, 1 +Inf, 2 -Inf), the NaN vertex count and
  /// the finite min / max. Combining the parts of blocks that tile the field (element-wise
  /// min of lo, max of hi, or of flags, sum of nan, min of vmin, max of vmax: MPI_MIN,
  /// MPI_MAX, MPI_BOR, MPI_SUM) gives exactly the parts of the whole field, in any order.
  struct Parts {
    std::int64_t cells[3] = {1, 1, 1};
    std::vector<double> lo, hi;  ///< +Inf / -Inf for a cell with no finite vertex
    std::vector<std::uint8_t> flags;
    std::uint64_t nan = 0;
    double vmin = INFINITY, vmax = -INFINITY;
    /// Elements summarised, summed like nan; 0: the layout's dims (one field's vertices).
    /// A hierarchy of refinement levels counts the samples of every level (amr_summary_parts).
    std::uint64_t elements = 0;
  };
  /// Folds `b` into `a` as the ranks' reductions above combine them (parts of the same cells;
  /// other cell counts are refused by name, std::invalid_argument): exact in any order.
  static void combine(Parts& a, const Parts& b);
  /// The parts of one block: `block` holds the global vertices [offset, offset + block.dims)
  /// of a field of `global_dims`; cells are the global field's (as majorant_edge of the global
  /// field gives `edge`); cells the block does not touch are left empty.
  static Parts partial(const FieldView& block, const std::int64_t offset[3], const std::int64_t global_dims[3],
                       int edge);
  /// Merges one block's part into `parts` (made by partial() for the same global_dims and
  /// edge), exactly as combining partial() of the block would, at the cost of the block's own
  /// vertices and the cells it touches: the way to summarise many small blocks of one rank.
  /// Throws std::invalid_argument as partial() does, or when `parts` has other cells.
  static void accumulate(Parts& parts, const FieldView& block, const std::int64_t offset[3],
                         const std::int64_t global_dims[3], int edge);
  /// The summary of combined parts (of the whole field); `layout` is recorded for matches().
  static std::shared_ptr<const FieldSummary> from_parts(Parts&& parts, const FieldLayout& layout, int edge);

  /// make_shared of the constructor, as prepare() and its callers keep it.
  static std::shared_ptr<const FieldSummary> build(const FieldView& field, int edge);

  const FieldLayout& layout() const { return m_layout; }
  int edge() const { return m_edge; }
  /// True iff built from a field of the same layout with the same edge. Says nothing about
  /// the values (see the file comment).
  bool matches(const FieldView& field, int edge) const;

  /// Macrocells along i, j, k (each >= 1).
  const std::int64_t* cells() const { return m_nc; }
  std::int64_t cell_count() const { return m_nc[0] * m_nc[1] * m_nc[2]; }
  std::int64_t cell_index(std::int64_t cx, std::int64_t cy, std::int64_t cz) const {
    return (cz * m_nc[1] + cy) * m_nc[0] + cx;
  }
  std::span<const CellRange> ranges() const { return m_range; }

  std::uint64_t nan_vertices() const { return m_nan; }
  /// Elements the summary covers (what nan_vertices() is a part of): the field's vertices, or
  /// every level's samples of a hierarchy.
  std::uint64_t element_count() const { return m_elements; }
  /// True iff at least one vertex is finite.
  bool has_finite() const { return m_vmin <= m_vmax; }
  /// Finite min / max over all vertices ({0,0} when none is finite; has_finite() tells).
  double value_min() const { return has_finite() ? m_vmin : 0.0; }
  double value_max() const { return has_finite() ? m_vmax : 0.0; }

 private:
  FieldSummary() = default;  ///< for from_parts
  FieldLayout m_layout;
  int m_edge = 1;
  std::int64_t m_nc[3] = {1, 1, 1};
  std::vector<CellRange> m_range;
  std::uint64_t m_nan = 0;
  std::uint64_t m_elements = 0;
  double m_vmin = INFINITY, m_vmax = -INFINITY;  ///< +Inf / -Inf when no vertex is finite
};

}  // namespace tessera
