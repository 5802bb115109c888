#pragma once
/// MacroSpans: for one macrocell grid over a mesh's layout (mesh_summary.h), the macrocells
/// each element's box meets, stored per cell of the mesh's input (its domains' cells in order,
/// ghosts included) so that a summary reads the connectivity and values in the order they lie
/// in memory. The layout's canonical order scatters a structured block's cells across its
/// arrays (sorted by centroid x first): folding in that order spent most of an unchanged mesh's
/// prepare waiting on cache misses.
///
/// Built from the layout's boxes alone (never the values), so it is kept with the layout
/// (MeshLayout::macro_spans) and serves every later summary over the same grid. A cell that is
/// not an element of the layout (a ghost when it was built) has no span.
#include "mesh/element_range.h"

#include <cstdint>
#include <span>
#include <vector>

namespace tessera {

class MeshLayout;

/// The macrocells [c, c + n) per axis that one element's padded box meets (MacroGrid::span),
/// `first` the linear index of its lowest one; n[0] == 0: not an element of the layout.
struct MacroSpan {
  std::int64_t first = 0;
  std::uint32_t n[3] = {0, 0, 0};
};

class MacroSpans {
 public:
  /// The spans of `layout`'s elements over `grid` (its cells fewer than 2^32 per axis; a grid
  /// of more is refused by name). O(cells of the input); the elements over threads.
  MacroSpans(const MeshLayout& layout, const MacroGrid& grid);

  /// Whether these spans are over `grid` (the same origin, spacing, cells and edge).
  bool over(const MacroGrid& grid) const;
  std::size_t domain_count() const { return m_offset.size() - 1; }
  /// Every cell's span, the domains one after the other (domain d from offset(d)).
  std::span<const MacroSpan> all() const { return m_span; }
  std::int64_t offset(std::size_t d) const { return m_offset[d]; }
  /// The domain of cell `c` (< all().size()) in all()'s numbering: O(log domains).
  std::size_t domain_of(std::size_t c) const;
  std::uint64_t bytes() const { return m_span.size() * sizeof(MacroSpan) + m_offset.size() * sizeof(std::int64_t); }

 private:
  MacroGrid m_grid;
  std::vector<std::int64_t> m_offset;  ///< per domain its first cell, then the total
  std::vector<MacroSpan> m_span;
};

}  // namespace tessera
