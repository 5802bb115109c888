/// MacroSpans (macro_spans.h): each layout element's macrocells, written at its input cell.
#include "mesh/macro_spans.h"

#include "mesh/mesh_layout.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace tessera {

MacroSpans::MacroSpans(const MeshLayout& layout, const MacroGrid& grid) : m_grid(grid) {
  for (int a = 0; a < 3; ++a)
    if (grid.cells[a] > static_cast<std::int64_t>(std::numeric_limits<std::uint32_t>::max()))
      throw std::invalid_argument("mesh: " + std::to_string(grid.cells[a]) + " macrocells along axis " +
                                  std::to_string(a) + ", at most 2^32 - 1 are supported");
  const std::size_t domains = layout.domain_count();
  m_offset.assign(domains + 1, 0);
  for (std::size_t d = 0; d < domains; ++d) m_offset[d + 1] = m_offset[d] + layout.domain_cells(d);
  m_span.assign(static_cast<std::size_t>(m_offset[domains]), MacroSpan{});
  // Each element writes its own input cell (the layout lists each real cell once): no races
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, layout.element_count(), 8192), [&](const auto& r) {
    for (std::size_t e = r.begin(); e != r.end(); ++e) {
      const MeshElementRef& ref = layout.element(e);
      std::int64_t c0[3], c1[3];
      grid.span(layout.box(e), c0, c1);
      MacroSpan& s = m_span[static_cast<std::size_t>(m_offset[static_cast<std::size_t>(ref.domain)] + ref.cell)];
      s.first = (c0[2] * grid.cells[1] + c0[1]) * grid.cells[0] + c0[0];
      for (int a = 0; a < 3; ++a) s.n[a] = static_cast<std::uint32_t>(c1[a] - c0[a] + 1);
    }
  });
}

std::size_t MacroSpans::domain_of(std::size_t c) const {
  // The last domain starting at or before c (empty domains start where the next one does)
  const auto it = std::upper_bound(m_offset.begin(), m_offset.end(), static_cast<std::int64_t>(c));
  return static_cast<std::size_t>(it - m_offset.begin()) - 1;
}

bool MacroSpans::over(const MacroGrid& g) const {
  for (int a = 0; a < 3; ++a)
    if (g.origin[a] != m_grid.origin[a] || g.spacing[a] != m_grid.spacing[a] || g.cells[a] != m_grid.cells[a])
      return false;
  return g.edge == m_grid.edge;
}

}  // namespace tessera
