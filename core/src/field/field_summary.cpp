#include <tessera/field_summary.h>

#include "field/summary_accumulate.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace tessera {
namespace {

using summary_detail::accumulate_values;
using summary_detail::canonical;
using summary_detail::check_block_inside;
using summary_detail::check_parts;
using summary_detail::cells_along;
using summary_detail::kEmpty;
using summary_detail::kInf;
using summary_detail::merge_value;

/// Slabs aimed at when the field has few cell layers along k (a fixed number, so that the
/// split, and with it the result, does not depend on the thread count).
constexpr std::int64_t kTargetSlabs = 32;

/// b folded into a, b after a: among equal values the earlier one stays (as std::min/max).
void merge(CellRange& a, const CellRange& b) {
  a.lo = b.lo < a.lo ? b.lo : a.lo;
  a.hi = a.hi < b.hi ? b.hi : a.hi;
  a.nan = a.nan || b.nan;
  a.pos_inf = a.pos_inf || b.pos_inf;
  a.neg_inf = a.neg_inf || b.neg_inf;
}

template <class T>
double load(const unsigned char* p) {
  T v;
  __builtin_memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

/// Range and NaN count of n vertices from p, sx bytes apart, in order.
template <class T>
CellRange scan_run(const unsigned char* p, std::int64_t sx, std::int64_t n, std::uint64_t& nans) {
  double lo = kInf, hi = -kInf;
  if constexpr (std::is_integral_v<T>) {
    for (std::int64_t i = 0; i < n; ++i) {
      const double v = load<T>(p + i * sx);
      lo = v < lo ? v : lo;
      hi = hi < v ? v : hi;
    }
    return {lo, hi, false, false, false};
  } else {
    std::uint64_t nan = 0;
    bool pinf = false, ninf = false;
    for (std::int64_t i = 0; i < n; ++i) {
      const double v = canonical(load<T>(p + i * sx));
      const bool finite = v - v == 0.0;  // false for NaN and +-Inf
      lo = finite && v < lo ? v : lo;
      hi = finite && hi < v ? v : hi;
      nan += v != v;
      pinf = pinf || v == kInf;
      ninf = ninf || v == -kInf;
    }
    nans += nan;
    return {lo, hi, nan != 0, pinf, ninf};
  }
}

/// Rows [k_begin, k_end) of cell layer ck, plus (extra_row) row k_end for the ranges only:
/// the +1 overlap with the next layer, which owns that row.
struct Slab {
  std::int64_t ck, k_begin, k_end;
  bool extra_row;
  CellRange* out;            ///< nc[0]*nc[1] cells of layer ck (or a partial copy)
  std::uint64_t nans = 0;    ///< over the owned rows
  CellRange total = kEmpty;  ///< finite min/max over the owned rows, in order
};

template <class T>
void scan_slab(const FieldView& f, int edge, const std::int64_t nc[3], Slab& s) {
  const auto* base = static_cast<const unsigned char*>(f.data);
  const std::int64_t sx = f.byte_strides[0], sy = f.byte_strides[1], sz = f.byte_strides[2];
  const std::int64_t nx = f.dims[0], ny = f.dims[1];
  std::vector<CellRange> parts(static_cast<std::size_t>(nc[0]));
  const std::int64_t k_last = s.extra_row ? s.k_end : s.k_end - 1;
  for (std::int64_t k = s.k_begin; k <= k_last; ++k) {
    const bool owned = k < s.k_end;
    for (std::int64_t j = 0; j < ny; ++j) {
      const unsigned char* row = base + j * sy + k * sz;
      // Owned parts of the row: cell ci owns vertices [ci*E, (ci+1)*E), the last one to nx
      std::uint64_t nans = 0;
      for (std::int64_t ci = 0; ci < nc[0]; ++ci) {
        const std::int64_t i0 = ci * edge, i1 = ci + 1 == nc[0] ? nx : (ci + 1) * edge;
        parts[ci] = scan_run<T>(row + i0 * sx, sx, i1 - i0, nans);
      }
      if (owned) {
        s.nans += nans;
        for (const CellRange& p : parts) merge(s.total, p);
      }
      // Each cell's row segment (its part plus the first vertex of the next) into the one
      // or two cells along j that hold row j
      const std::int64_t cj0 = std::min(std::max<std::int64_t>(0, (j - 1) / edge), nc[1] - 1);
      const std::int64_t cj1 = std::min(j / edge, nc[1] - 1);
      for (std::int64_t ci = 0; ci < nc[0]; ++ci) {
        CellRange seg = parts[ci];
        if (ci + 1 < nc[0]) merge_value(seg, load<T>(row + (ci + 1) * edge * sx));
        merge(s.out[cj0 * nc[0] + ci], seg);
        if (cj1 != cj0) merge(s.out[cj1 * nc[0] + ci], seg);
      }
    }
  }
}

}  // namespace

FieldLayout FieldLayout::of(const FieldView& field) {
  FieldLayout l;
  l.data = field.data;
  l.dtype = field.dtype;
  for (int a = 0; a < 3; ++a) {
    l.dims[a] = field.dims[a];
    l.byte_strides[a] = field.byte_strides[a];
  }
  return l;
}

bool FieldLayout::operator==(const FieldLayout& o) const {
  if (data != o.data || dtype != o.dtype) return false;
  for (int a = 0; a < 3; ++a)
    if (dims[a] != o.dims[a] || byte_strides[a] != o.byte_strides[a]) return false;
  return true;
}

int majorant_edge(const FieldView& field, const IntegratorDesc& integrator) {
  if (integrator.majorant != MajorantMode::Global) return integrator.macrocell;
  const std::int64_t max_dim = std::max({field.dims[0], field.dims[1], field.dims[2]});
  return static_cast<int>(std::clamp<std::int64_t>(max_dim, 1, 1 << 30));
}

FieldSummary::FieldSummary(const FieldView& field, int edge)
    : m_layout(FieldLayout::of(field)), m_edge(edge), m_vmin(kInf), m_vmax(-kInf) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  for (int a = 0; a < 3; ++a) m_nc[a] = cells_along(field.dims[a], edge);
  m_elements = static_cast<std::uint64_t>(field.vertex_count());
  const std::int64_t layer_cells = m_nc[0] * m_nc[1];
  m_range.assign(static_cast<std::size_t>(cell_count()), kEmpty);

  // Slabs: each cell layer along k alone, or split into a few when there are few layers
  const std::int64_t nz = field.dims[2];
  const std::int64_t per_layer = std::max<std::int64_t>(1, (kTargetSlabs + m_nc[2] - 1) / m_nc[2]);
  std::vector<Slab> slabs;
  std::vector<std::vector<CellRange>> partial;  // per slab of a split layer
  std::vector<std::int64_t> first_slab(static_cast<std::size_t>(m_nc[2] + 1));
  for (std::int64_t ck = 0; ck < m_nc[2]; ++ck) {
    first_slab[ck] = static_cast<std::int64_t>(slabs.size());
    const std::int64_t k0 = ck * edge, k1 = ck + 1 == m_nc[2] ? nz : (ck + 1) * edge;
    const std::int64_t n = std::min(per_layer, k1 - k0);
    for (std::int64_t p = 0; p < n; ++p) {
      Slab s{ck, k0 + (k1 - k0) * p / n, k0 + (k1 - k0) * (p + 1) / n, p + 1 == n && k1 < nz,
             m_range.data() + ck * layer_cells};
      slabs.push_back(s);
    }
  }
  first_slab[m_nc[2]] = static_cast<std::int64_t>(slabs.size());
  partial.resize(slabs.size());
  for (std::int64_t ck = 0; ck < m_nc[2]; ++ck)
    if (first_slab[ck + 1] - first_slab[ck] > 1)
      for (std::int64_t s = first_slab[ck]; s < first_slab[ck + 1]; ++s) {
        partial[s].assign(static_cast<std::size_t>(layer_cells), kEmpty);
        slabs[s].out = partial[s].data();
      }

  // Scan, in parallel over slabs; each slab writes only its own cells
  dispatch_dtype(field, [&](auto view) {
    using T = typename decltype(view)::value_type;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, slabs.size(), 1), [&](const auto& r) {
      for (std::size_t s = r.begin(); s != r.end(); ++s) scan_slab<T>(field, edge, m_nc, slabs[s]);
    });
  });

  // Split layers: their slabs' partial cells, merged in k order
  for (std::int64_t ck = 0; ck < m_nc[2]; ++ck) {
    if (first_slab[ck + 1] - first_slab[ck] <= 1) continue;
    CellRange* out = m_range.data() + ck * layer_cells;
    for (std::int64_t s = first_slab[ck]; s < first_slab[ck + 1]; ++s)
      for (std::int64_t c = 0; c < layer_cells; ++c) merge(out[c], partial[s][c]);
  }
  CellRange total = kEmpty;
  for (const Slab& s : slabs) {
    m_nan += s.nans;
    merge(total, s.total);
  }
  m_vmin = total.lo;
  m_vmax = total.hi;
}

std::shared_ptr<const FieldSummary> FieldSummary::build(const FieldView& field, int edge) {
  return std::make_shared<const FieldSummary>(field, edge);
}

FieldSummary::Parts FieldSummary::partial(const FieldView& block, const std::int64_t offset[3],
                                          const std::int64_t global_dims[3], int edge) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  Parts parts;
  for (int a = 0; a < 3; ++a) parts.cells[a] = cells_along(global_dims[a], edge);
  const auto n = static_cast<std::size_t>(parts.cells[0] * parts.cells[1] * parts.cells[2]);
  parts.lo.assign(n, kInf);
  parts.hi.assign(n, -kInf);
  parts.flags.assign(n, 0);
  accumulate(parts, block, offset, global_dims, edge);
  return parts;
}

void FieldSummary::accumulate(Parts& parts, const FieldView& block, const std::int64_t offset[3],
                              const std::int64_t global_dims[3], int edge) {
  check_parts(parts, global_dims, edge);
  if (block.data == nullptr) return;
  block.validate("block");
  check_block_inside(block.dims, offset, global_dims);
  dispatch_dtype(block, [&](auto view) {
    accumulate_values(parts, block.dims, offset, edge,
                      [&](std::int64_t i, std::int64_t j, std::int64_t k) { return view.load(i, j, k); });
  });
}

void FieldSummary::combine(Parts& a, const Parts& b) {
  if (b.lo.size() != a.lo.size() || b.hi.size() != a.lo.size() || b.flags.size() != a.lo.size() ||
      a.hi.size() != a.lo.size() || a.flags.size() != a.lo.size())
    throw std::invalid_argument("field summary: parts of " + std::to_string(b.lo.size()) +
                                " cells combined into parts of " + std::to_string(a.lo.size()));
  for (std::size_t n = 0; n < a.lo.size(); ++n) {
    a.lo[n] = std::min(a.lo[n], b.lo[n]);
    a.hi[n] = std::max(a.hi[n], b.hi[n]);
    a.flags[n] |= b.flags[n];
  }
  a.nan += b.nan;
  a.elements += b.elements;
  a.vmin = std::min(a.vmin, b.vmin);
  a.vmax = std::max(a.vmax, b.vmax);
}

std::shared_ptr<const FieldSummary> FieldSummary::from_parts(Parts&& parts, const FieldLayout& layout, int edge) {
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  const std::int64_t n = parts.cells[0] * parts.cells[1] * parts.cells[2];
  if (parts.cells[0] < 1 || parts.cells[1] < 1 || parts.cells[2] < 1 ||
      parts.lo.size() != static_cast<std::size_t>(n) || parts.hi.size() != parts.lo.size() ||
      parts.flags.size() != parts.lo.size())
    throw std::invalid_argument("field summary parts: " + std::to_string(parts.lo.size()) + " lo, " +
                                std::to_string(parts.hi.size()) + " hi, " + std::to_string(parts.flags.size()) +
                                " flags for " + std::to_string(n) + " cells");
  std::shared_ptr<FieldSummary> s(new FieldSummary());
  s->m_layout = layout;
  s->m_edge = edge;
  s->m_elements = parts.elements ? parts.elements
                                 : static_cast<std::uint64_t>(std::max<std::int64_t>(0, layout.dims[0])) *
                                       static_cast<std::uint64_t>(std::max<std::int64_t>(0, layout.dims[1])) *
                                       static_cast<std::uint64_t>(std::max<std::int64_t>(0, layout.dims[2]));
  for (int a = 0; a < 3; ++a) s->m_nc[a] = parts.cells[a];
  s->m_range.resize(static_cast<std::size_t>(n));
  for (std::size_t c = 0; c < s->m_range.size(); ++c)
    s->m_range[c] = CellRange{parts.lo[c], parts.hi[c], (parts.flags[c] & 1) != 0, (parts.flags[c] & 2) != 0,
                              (parts.flags[c] & 4) != 0};
  s->m_nan = parts.nan;
  s->m_vmin = parts.vmin;
  s->m_vmax = parts.vmax;
  return s;
}

bool FieldSummary::matches(const FieldView& field, int edge) const {
  return edge == m_edge && FieldLayout::of(field) == m_layout;
}

}  // namespace tessera
