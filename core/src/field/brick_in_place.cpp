/// BrickCache::set_in_place: the table that lets PagedFieldView::load read the rank's other
/// own blocks in place, cell by cell, without a search (brick_cache.h).
#include <tessera/brick_cache.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace tessera {
namespace {

std::string box_text(const std::int64_t offset[3], const std::int64_t dims[3]) {
  std::string t;
  for (int a = 0; a < 3; ++a)
    t += (a ? ", " : "") + std::string("[") + std::to_string(offset[a]) + ", " + std::to_string(offset[a] + dims[a]) +
         ")";
  return t;
}

}  // namespace

std::uint64_t BrickCache::in_place_entries(const BrickGrid& grid) {
  return std::max<std::uint64_t>(static_cast<std::uint64_t>(grid.brick_count()), std::uint64_t{1} << 18);
}

void BrickCache::set_in_place(std::span<const InPlaceBlock> blocks) {
  m_in_place.clear();
  m_table = InPlaceTable{};
  m_in_place_vertices = 0;
  if (blocks.empty()) return;
  if (blocks.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw std::invalid_argument("brick cache: " + std::to_string(blocks.size()) + " in-place blocks, at most " +
                                std::to_string(std::numeric_limits<std::int32_t>::max()));
  const auto fail = [&](std::size_t d, const std::string& why) {
    m_in_place.clear();
    m_table = InPlaceTable{};
    m_in_place_vertices = 0;
    throw std::invalid_argument("brick cache: in-place block " + std::to_string(d) + " " + why);
  };
  // Every block checked; the bounding box of them all
  std::int64_t blo[3], bhi[3];
  for (int a = 0; a < 3; ++a) blo[a] = m_grid.dims[a], bhi[a] = 0;
  m_in_place.reserve(blocks.size());
  for (std::size_t d = 0; d < blocks.size(); ++d) {
    const InPlaceBlock& blk = blocks[d];
    try {
      blk.view.validate("in-place block");
    } catch (const std::exception& e) {
      fail(d, std::string("is invalid: ") + e.what());
    }
    if (blk.view.dtype != m_grid.dtype)
      fail(d, std::string("is ") + dtype_name(blk.view.dtype) + ", the cache's grid " + dtype_name(m_grid.dtype));
    std::int64_t shift_bytes = 0;
    for (int a = 0; a < 3; ++a) {
      if (blk.offset[a] < 0 || blk.offset[a] + blk.view.dims[a] > m_grid.dims[a])
        fail(d, "at " + box_text(blk.offset, blk.view.dims) + " is not inside the grid's " +
                    std::to_string(m_grid.dims[0]) + "x" + std::to_string(m_grid.dims[1]) + "x" +
                    std::to_string(m_grid.dims[2]) + " vertices");
      blo[a] = std::min(blo[a], blk.offset[a]);
      bhi[a] = std::max(bhi[a], blk.offset[a] + blk.view.dims[a]);
      shift_bytes += blk.offset[a] * blk.view.byte_strides[a];
    }
    InPlaceAddress& at = m_in_place.emplace_back();
    for (int a = 0; a < 3; ++a) at.byte_strides[a] = blk.view.byte_strides[a];
    at.origin = reinterpret_cast<std::intptr_t>(blk.view.data) - static_cast<std::intptr_t>(shift_bytes);
  }
  // The finest cells whose table over the box fits (cells of a brick always fit: the box is
  // inside the grid)
  const std::uint64_t room = in_place_entries(m_grid);
  InPlaceTable t;
  for (t.shift = 1;; ++t.shift) {
    std::uint64_t n = 1;
    for (int a = 0; a < 3; ++a) {
      t.lo[a] = (blo[a] >> t.shift) << t.shift;
      t.cells[a] = static_cast<std::uint64_t>(((bhi[a] - 1) >> t.shift) - (blo[a] >> t.shift) + 1);
      n *= t.cells[a];
    }
    if (n <= room || t.shift >= m_grid.shift) break;
  }
  std::int32_t* cell = m_in_place_cells.get();
  std::fill(cell, cell + t.cells[0] * t.cells[1] * t.cells[2], -1);
  t.cell = cell;
  t.at = m_in_place.data();
  // Each block's cells: along each axis those whose box [c 2^t, min((c + 1) 2^t, dims)) lies
  // in [offset, offset + dims)
  const std::int64_t edge = std::int64_t{1} << t.shift;
  for (std::size_t d = 0; d < blocks.size(); ++d) {
    const InPlaceBlock& blk = blocks[d];
    std::int64_t first[3], last[3];
    bool any = true;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t lo = blk.offset[a], hi = blk.offset[a] + blk.view.dims[a];
      first[a] = (lo + edge - 1) >> t.shift;
      last[a] = hi == m_grid.dims[a] ? (hi - 1) >> t.shift : (hi >> t.shift) - 1;
      if (first[a] > last[a]) any = false;
    }
    if (!any) continue;
    const std::int64_t c0[3] = {t.lo[0] >> t.shift, t.lo[1] >> t.shift, t.lo[2] >> t.shift};
    for (std::int64_t z = first[2]; z <= last[2]; ++z)
      for (std::int64_t y = first[1]; y <= last[1]; ++y)
        for (std::int64_t x = first[0]; x <= last[0]; ++x) {
          const auto at = static_cast<std::size_t>(
              ((static_cast<std::uint64_t>(z - c0[2]) * t.cells[1]) + static_cast<std::uint64_t>(y - c0[1])) *
                  t.cells[0] +
              static_cast<std::uint64_t>(x - c0[0]));
          if (cell[at] >= 0)
            fail(d,
                 "at " + box_text(blk.offset, blk.view.dims) + " overlaps in-place block " + std::to_string(cell[at]));
          cell[at] = static_cast<std::int32_t>(d);
          std::int64_t v = 1;
          for (int a = 0; a < 3; ++a) {
            const std::int64_t g = a == 0 ? x : a == 1 ? y : z;
            v *= std::min(m_grid.dims[a], (g + 1) << t.shift) - (g << t.shift);
          }
          m_in_place_vertices += static_cast<std::uint64_t>(v);
        }
  }
  m_table = t;
}

}  // namespace tessera
