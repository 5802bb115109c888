#include "scene/amr_tables.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace tessera {
namespace {

/// One level's stencil-table geometry: stencil cells [lo, lo + ext) in cells of 2^bits.
struct TableShape {
  std::int64_t lo[3] = {0, 0, 0}, ext[3] = {0, 0, 0};
  std::uint64_t cells[3] = {0, 0, 0};
  int bits = 0;
  bool empty = true;
  std::uint64_t entries() const { return cells[0] * cells[1] * cells[2]; }
};

TableShape shape_of(const AmrField& f, Association assoc, int l) {
  TableShape s;
  std::int64_t blo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, bhi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
  for (const AmrPatch& p : f.patches) {
    if (p.level != l) continue;
    s.empty = false;
    for (int a = 0; a < 3; ++a) {
      blo[a] = std::min(blo[a], p.offset[a]);
      bhi[a] = std::max(bhi[a], p.offset[a] + p.view.dims[a]);
    }
  }
  if (s.empty) return s;
  for (int a = 0; a < 3; ++a) {
    s.lo[a] = blo[a];
    s.ext[a] = std::max<std::int64_t>(bhi[a] - 1 - blo[a], 1);  // stencil cells with a present sample pair
  }
  for (s.bits = 0;; ++s.bits) {
    for (int a = 0; a < 3; ++a)
      s.cells[a] = static_cast<std::uint64_t>((s.ext[a] + (std::int64_t{1} << s.bits) - 1) >> s.bits);
    if (s.entries() <= AmrTables::kMaxTableEntries) break;
  }
  return s;
}

/// Per axis, the table cells [c0, c1] that stencil cells [s0, s1) fall in (empty: c0 > c1).
void cell_range(const TableShape& s, int a, std::int64_t s0, std::int64_t s1, std::int64_t* c0, std::int64_t* c1) {
  s0 = std::max(s0, s.lo[a]);
  s1 = std::min(s1, s.lo[a] + s.ext[a]);
  if (s0 >= s1) {
    *c0 = 1;
    *c1 = 0;
    return;
  }
  *c0 = (s0 - s.lo[a]) >> s.bits;
  *c1 = (s1 - 1 - s.lo[a]) >> s.bits;
}

/// The stencil cells [lo, hi) wholly in patch p (both samples of each axis in it) and those
/// using some sample of it, along axis a of a level with n samples.
void patch_cells(const AmrPatch& p, int a, std::int64_t n, std::int64_t* full_lo, std::int64_t* full_hi,
                 std::int64_t* touch_lo, std::int64_t* touch_hi) {
  const std::int64_t o = p.offset[a], d = p.view.dims[a];
  *full_lo = o;
  *full_hi = n == 1 ? o + d : o + d - 1;
  *touch_lo = o - 1;
  *touch_hi = o + d;
}

std::int64_t cells_along(std::int64_t dims, int edge) {
  return std::max<std::int64_t>(1, (dims - 1 + edge - 1) / edge);
}

}  // namespace

void AmrTables::build(const AmrField& f, Association assoc, int edge, const std::int64_t cells[3],
                      const PagedFieldView* paged) {
  m_view = AmrFieldView{};
  if (paged) m_view.paged = *paged;
  m_view.dtype = f.dtype;
  m_view.nlevels = f.nlevels;
  // Patch addresses
  m_patch.assign(f.patches.size(), AmrPatchAddress{});
  for (std::size_t n = 0; n < f.patches.size(); ++n) {
    const AmrPatch& p = f.patches[n];
    AmrPatchAddress& A = m_patch[n];
    A.remote = p.view.data == nullptr;
    for (int a = 0; a < 3; ++a) A.vbase[a] = f.layout.base[p.level][a];
    std::intptr_t origin = reinterpret_cast<std::intptr_t>(p.view.data);
    for (int a = 0; a < 3; ++a) {
      A.s[a] = p.view.byte_strides[a];
      A.lo[a] = p.offset[a];
      A.hi[a] = p.offset[a] + p.view.dims[a];
      origin -= static_cast<std::intptr_t>(p.offset[a] * p.view.byte_strides[a]);
    }
    A.origin = origin;
  }
  m_view.patch = m_patch.data();
  // Levels
  for (int l = 0; l < f.nlevels; ++l) {
    AmrLevelView& L = m_view.level[l];
    const double R = static_cast<double>(f.scale(l));
    L.scale = R;
    L.shift = assoc == Association::Cell ? 0.5 * R - 0.5 : 0.0;
    for (int a = 0; a < 3; ++a) {
      L.n[a] = f.level_dims(l, a, assoc);
      L.hi_index[a] = static_cast<double>(L.n[a] - 1);
    }
    const TableShape s = shape_of(f, assoc, l);
    m_table[l].clear();
    m_first[l].clear();
    m_cand[l].clear();
    if (s.empty) continue;  // cells 0: every lookup at this level misses
    m_table[l].assign(s.entries(), -1);
    std::vector<std::pair<std::uint64_t, std::int32_t>> shared;  // (table cell, patch) of partial cells
    for (std::size_t n = 0; n < f.patches.size(); ++n) {
      const AmrPatch& p = f.patches[n];
      if (p.level != l) continue;
      std::int64_t flo[3], fhi[3], c0[3], c1[3];
      for (int a = 0; a < 3; ++a) {
        std::int64_t tlo, thi;
        patch_cells(p, a, L.n[a], &flo[a], &fhi[a], &tlo, &thi);
        cell_range(s, a, tlo, thi, &c0[a], &c1[a]);
      }
      for (std::int64_t z = c0[2]; z <= c1[2]; ++z)
        for (std::int64_t y = c0[1]; y <= c1[1]; ++y)
          for (std::int64_t x = c0[0]; x <= c1[0]; ++x) {
            const std::int64_t c[3] = {x, y, z};
            bool whole = true;
            for (int a = 0; a < 3 && whole; ++a) {
              const std::int64_t lo = s.lo[a] + (c[a] << s.bits);
              const std::int64_t hi = lo + (std::int64_t{1} << s.bits);  // (a partial last cell is not whole)
              whole = lo >= flo[a] && hi <= fhi[a];
            }
            const std::uint64_t e =
                (static_cast<std::uint64_t>(z) * s.cells[1] + static_cast<std::uint64_t>(y)) * s.cells[0] +
                static_cast<std::uint64_t>(x);
            if (whole) m_table[l][e] = static_cast<std::int32_t>(n);
            else shared.emplace_back(e, static_cast<std::int32_t>(n));
          }
    }
    // Candidate lists of the cells no single patch holds wholly, in (cell, patch) order
    std::sort(shared.begin(), shared.end());
    for (std::size_t q = 0; q < shared.size();) {
      const std::uint64_t e = shared[q].first;
      std::size_t r = q;
      while (r < shared.size() && shared[r].first == e) ++r;
      if (m_table[l][e] == -1) {
        m_table[l][e] = -2 - static_cast<std::int32_t>(m_first[l].size());
        m_first[l].push_back(static_cast<std::uint32_t>(m_cand[l].size()));
        for (std::size_t k = q; k < r; ++k) m_cand[l].push_back(shared[k].second);
      }
      q = r;
    }
    m_first[l].push_back(static_cast<std::uint32_t>(m_cand[l].size()));
    L.table = m_table[l].data();
    L.first = m_first[l].data();
    L.cand = m_cand[l].data();
    L.shift_bits = s.bits;
    for (int a = 0; a < 3; ++a) {
      L.lo[a] = s.lo[a];
      L.cells[a] = s.cells[a];
    }
  }
  // Per macrocell, the finest level a patch's samples reach: a patch's samples serve the
  // stencil cells [o - 1, o + d), i.e. q in [o - 1, o + d], i.e. p = (q - shift) / scale
  const double E = static_cast<double>(edge);
  m_view.inv_edge = 1.0 / E;
  for (int a = 0; a < 3; ++a) m_view.nc[a] = cells[a];
  m_finest.assign(static_cast<std::size_t>(cells[0] * cells[1] * cells[2]), 0);
  for (const AmrPatch& p : f.patches) {
    if (p.level == 0) continue;
    const AmrLevelView& L = m_view.level[p.level];
    std::int64_t c0[3], c1[3];
    for (int a = 0; a < 3; ++a) {
      const double plo = (static_cast<double>(p.offset[a] - 1) - L.shift) / L.scale;
      const double phi = (static_cast<double>(p.offset[a] + p.view.dims[a]) - L.shift) / L.scale;
      // A margin of 1e-6 sample against rounding in the kernels' q = p * scale + shift
      c0[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((plo - 1e-6) / E)), 0, cells[a] - 1);
      c1[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((phi + 1e-6) / E)), 0, cells[a] - 1);
    }
    for (std::int64_t z = c0[2]; z <= c1[2]; ++z)
      for (std::int64_t y = c0[1]; y <= c1[1]; ++y)
        for (std::int64_t x = c0[0]; x <= c1[0]; ++x) {
          std::uint8_t& v = m_finest[static_cast<std::size_t>((z * cells[1] + y) * cells[0] + x)];
          v = std::max<std::uint8_t>(v, static_cast<std::uint8_t>(p.level));
        }
  }
  m_view.finest = m_finest.data();
}

std::uint64_t AmrTables::bytes() const {
  std::uint64_t b = m_patch.size() * sizeof(AmrPatchAddress) + m_finest.size();
  for (int l = 0; l < 8; ++l) b += 4 * (m_table[l].size() + m_first[l].size() + m_cand[l].size());
  return b;
}

std::uint64_t AmrTables::estimate(const AmrField& f, Association assoc, int edge) {
  std::uint64_t b = f.patches.size() * sizeof(AmrPatchAddress);
  std::uint64_t macro = 1;
  for (int a = 0; a < 3; ++a) macro *= static_cast<std::uint64_t>(cells_along(f.dims[a], edge));
  b += macro;
  for (int l = 0; l < f.nlevels && l < kMaxAmrLevels; ++l) {
    const TableShape s = shape_of(f, assoc, l);
    if (s.empty) continue;
    b += 4 * (s.entries() + 1);
    // Candidates: at most the touched table cells of each patch (8 bytes each with its list)
    for (const AmrPatch& p : f.patches) {
      if (p.level != l) continue;
      std::uint64_t touched = 1;
      for (int a = 0; a < 3; ++a) {
        std::int64_t flo, fhi, tlo, thi, c0, c1;
        patch_cells(p, a, f.level_dims(l, a, assoc), &flo, &fhi, &tlo, &thi);
        cell_range(s, a, tlo, thi, &c0, &c1);
        touched *= static_cast<std::uint64_t>(std::max<std::int64_t>(0, c1 - c0 + 1));
      }
      b += 8 * touched;
    }
  }
  return b;
}

std::uint64_t amr_table_bytes(const AmrField& field, Association assoc, int edge) {
  return AmrTables::estimate(field, assoc, edge);
}

}  // namespace tessera
