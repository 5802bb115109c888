#pragma once
/// AmrTables: the lookup tables of a hierarchy (kernel/amr_view.h says how the kernels use
/// them), built once per prepare from the patches' boxes alone (no value is read):
/// - per patch its address (AmrPatchAddress);
/// - per level a stencil table over the bounding box of the level's patches, at the finest
///   power-of-two cell edge whose table has at most kMaxTableEntries entries, with the
///   candidate lists of the cells that several patches (or a patch's border) share;
/// - per macrocell the finest level any patch reaches there.
/// Cost: O(table entries + the table cells each patch touches); bytes() says the memory.
#include <tessera/amr.h>

#include "kernel/amr_view.h"

#include <cstdint>
#include <vector>

namespace tessera {

class AmrTables {
 public:
  /// Entries of one level's stencil table at most (4 bytes each).
  static constexpr std::uint64_t kMaxTableEntries = std::uint64_t{1} << 20;

  /// Builds the tables of a checked hierarchy (check_amr) for macrocells of `edge` level-0
  /// samples, `cells` of them per axis; `paged` (distributed mode): the virtual grid remote
  /// patches are read through.
  void build(const AmrField& field, Association assoc, int edge, const std::int64_t cells[3],
             const PagedFieldView* paged = nullptr);
  /// The kernels' view (points into this object and the patches).
  const AmrFieldView& view() const { return m_view; }
  std::uint64_t bytes() const;
  /// Bytes build() allocates for `field` (candidate lists estimated by the patches' border
  /// cells), without building.
  static std::uint64_t estimate(const AmrField& field, Association assoc, int edge);

 private:
  std::vector<AmrPatchAddress> m_patch;
  std::vector<std::int32_t> m_table[8];
  std::vector<std::uint32_t> m_first[8];
  std::vector<std::int32_t> m_cand[8];
  std::vector<std::uint8_t> m_finest;
  AmrFieldView m_view;
};

}  // namespace tessera
