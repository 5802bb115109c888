/// MeshLayout (mesh_layout.h): gather the real elements, sort them canonically, lay the grid
/// over their box and list them per location cell.
#include "mesh/mesh_layout.h"

#include <tessera/render.h>

#include "mesh/element_range.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace tessera {
namespace {

/// One real element while building: where it is, for the canonical order.
struct Item {
  Vec3 centroid;
  double box[6];
  MeshElementRef ref;
};

/// The box of a set of elements (min / max: exact, so the same in any order of folding).
struct ElementBounds {
  Vec3 lo{INFINITY}, hi{-INFINITY};
};

/// Element e of domain d as an Item.
Item make_item(const DomainAccess& d, std::int32_t domain, std::int64_t e) {
  Item it;
  it.ref.cell = e;
  it.ref.domain = domain;
  std::int64_t idx[8];
  d.cell_vertices(e, idx);
  Vec3 sum(0.0);
  for (int k = 0; k < d.nv; ++k) sum += d.vertex(idx[k]);
  it.centroid = sum / static_cast<double>(d.nv);
  element_box(d, e, it.box);  // a device summarising the mesh computes the same boxes
  return it;
}

/// The canonical order: centroid, box, then the vertices' coordinates in the element's own
/// order (only where centroid and box tie): a function of the element's own coordinates.
struct CanonicalLess {
  const std::vector<DomainAccess>& domains;
  bool operator()(const Item& a, const Item& b) const {
    for (int k = 0; k < 3; ++k)
      if (a.centroid[k] != b.centroid[k]) return a.centroid[k] < b.centroid[k];
    for (int k = 0; k < 6; ++k)
      if (a.box[k] != b.box[k]) return a.box[k] < b.box[k];
    const DomainAccess &da = domains[static_cast<std::size_t>(a.ref.domain)],
                       &db = domains[static_cast<std::size_t>(b.ref.domain)];
    if (da.nv != db.nv) return da.nv < db.nv;
    std::int64_t ia[8], ib[8];
    da.cell_vertices(a.ref.cell, ia);
    db.cell_vertices(b.ref.cell, ib);
    for (int q = 0; q < da.nv; ++q) {
      const Vec3 va = da.vertex(ia[q]), vb = db.vertex(ib[q]);
      for (int k = 0; k < 3; ++k)
        if (va[k] != vb[k]) return va[k] < vb[k];
    }
    // The same element twice (overlapping cells, which the mesh must not have): by where it
    // is in the input, so that the order is total and a parallel sort's is the serial one's
    if (a.ref.domain != b.ref.domain) return a.ref.domain < b.ref.domain;
    return a.ref.cell < b.ref.cell;
  }
};

/// What MeshLayout::fits compares of one domain.
constexpr int kSignatureWords = 11;
void append_signature(const MeshDomain& d, std::vector<std::int64_t>& out) {
  const std::int64_t s[kSignatureWords] = {d.dims[0],
                                           d.dims[1],
                                           d.dims[2],
                                           d.structured() ? -1 : static_cast<std::int64_t>(d.shape),
                                           d.structured() ? -1 : static_cast<std::int64_t>(d.index_type),
                                           d.cell_count(),
                                           d.coords.count,
                                           static_cast<std::int64_t>(d.coords.dtype),
                                           d.ghosts.data ? d.ghosts.count : -1,
                                           0,
                                           0};
  out.insert(out.end(), s, s + kSignatureWords);
}

/// A run of elements [first, last) (canonical order) that covers every element reaching the
/// location cells of x index [i0, i1): the unit of build_location's work over threads.
struct SlabRun {
  std::size_t first = 0, last = 0;
  std::int64_t i0 = 0, i1 = 0;
};

/// Splits the location cells along x into slabs (up to four per thread) with, for each, the
/// run of elements that may reach it; one slab of everything when the mesh is small or its
/// elements so wide that the runs would overlap too much. `centroid_x`: per element in
/// canonical order (so non-decreasing); `nx`: location cells along x; loc_cell(0, x) and
/// span(e, 0, &c0, &c1): build_location's cell of a coordinate and cells of an element.
template <class LocCell, class Span>
std::vector<SlabRun> slab_runs(std::size_t n, const std::vector<double>& centroid_x, std::int64_t nx,
                               const LocCell& loc_cell, const Span& span) {
  const std::int64_t want = std::min<std::int64_t>(nx, 4 * tbb::this_task_arena::max_concurrency());
  if (n < 16384 || want < 2) return {SlabRun{0, n, 0, nx}};
  // Each element's centroid cell along x (non-decreasing in canonical order) and how far its
  // cells reach below and above it (integers: exact in any order of folding)
  std::vector<std::int64_t> cc(n);
  const auto reach = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 8192), std::pair<std::int64_t, std::int64_t>{0, 0},
      [&](const auto& r, std::pair<std::int64_t, std::int64_t> d) {
        for (std::size_t e = r.begin(); e != r.end(); ++e) {
          std::int64_t c0, c1;
          span(e, 0, &c0, &c1);
          cc[e] = loc_cell(0, centroid_x[e]);
          d.first = std::max(d.first, cc[e] - c0);
          d.second = std::max(d.second, c1 - cc[e]);
        }
        return d;
      },
      [](auto a, const auto& b) {
        return std::pair<std::int64_t, std::int64_t>{std::max(a.first, b.first), std::max(a.second, b.second)};
      });
  // An element reaching slab [i0, i1) has c1 >= i0 and c0 < i1, so its centroid cell cc is in
  // [i0 - above, i1 - 1 + below] (cc >= c1 - above >= i0 - above, cc <= c0 + below <= i1 - 1
  // + below; below = reach.first, above = reach.second)
  std::vector<SlabRun> slabs;
  std::size_t visits = 0;
  for (std::int64_t s = 0; s < want; ++s) {
    SlabRun run;
    run.i0 = nx * s / want;
    run.i1 = nx * (s + 1) / want;
    run.first = static_cast<std::size_t>(std::lower_bound(cc.begin(), cc.end(), run.i0 - reach.second) - cc.begin());
    run.last = static_cast<std::size_t>(std::upper_bound(cc.begin(), cc.end(), run.i1 - 1 + reach.first) - cc.begin());
    visits += run.last - run.first;
    slabs.push_back(run);
  }
  // Elements so wide that most slabs would visit most of them: one slab, one pass
  if (visits > 2 * n + 4096) return {SlabRun{0, n, 0, nx}};
  return slabs;
}

}  // namespace

MeshLayout::MeshLayout(const Mesh& mesh, const std::vector<DomainAccess>& domains) {
  for (const MeshDomain& d : mesh.domains) append_signature(d, m_signature);
  if (has_ghost_masks(mesh)) m_ghost_sums = geometry_sums(ghost_masks_only(mesh));
  const std::vector<double> centroid_x = gather(domains, mesh);
  place_grid();
  build_location(centroid_x);
}

bool mesh_layout_fits(const MeshLayout& layout, const Mesh& mesh) { return layout.fits(mesh); }

bool MeshLayout::fits(const Mesh& mesh) const {
  std::vector<std::int64_t> s;
  s.reserve(m_signature.size());
  for (const MeshDomain& d : mesh.domains) append_signature(d, s);
  return s == m_signature;
}

std::vector<double> MeshLayout::gather(const std::vector<DomainAccess>& domains, const Mesh& mesh) {
  // The real cells, in input order; their items over threads; the canonical order by a
  // parallel sort (a total order: the same result as a serial sort, any thread count)
  std::vector<MeshElementRef> real;
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const MeshDomain& md = mesh.domains[i];
    const std::int64_t cells = md.cell_count();
    for (std::int64_t e = 0; e < cells; ++e)
      if (!md.ghosts.is_ghost(e)) real.push_back(MeshElementRef{e, static_cast<std::int32_t>(i)});
  }
  if (real.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("mesh: " + std::to_string(real.size()) + " real cells, at most 2^32 - 1 are supported");
  std::vector<Item> items(real.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, real.size(), 4096), [&](const auto& r) {
    for (std::size_t e = r.begin(); e != r.end(); ++e) {
      const MeshElementRef& ref = real[e];
      items[e] = make_item(domains[static_cast<std::size_t>(ref.domain)], ref.domain, ref.cell);
    }
  });
  std::vector<MeshElementRef>().swap(real);
  tbb::parallel_sort(items.begin(), items.end(), CanonicalLess{domains});
  const std::size_t n = items.size();
  m_element.resize(n);
  m_box.resize(6 * n);
  // Copied out over threads, with each box's cube root volume for the voxel below; the box of
  // the mesh by min / max (exact in any order)
  std::vector<double> root(n), centroid_x(n);
  const auto bounds = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 8192), ElementBounds{},
      [&](const auto& r, ElementBounds b) {
        for (std::size_t e = r.begin(); e != r.end(); ++e) {
          const Item& it = items[e];
          m_element[e] = it.ref;
          centroid_x[e] = it.centroid.x;
          for (int a = 0; a < 3; ++a) {
            m_box[6 * e + a] = it.box[a];
            m_box[6 * e + 3 + a] = it.box[3 + a];
            b.lo[a] = std::min(b.lo[a], it.box[a]);
            b.hi[a] = std::max(b.hi[a], it.box[3 + a]);
          }
          root[e] = std::cbrt((it.box[3] - it.box[0]) * (it.box[4] - it.box[1]) * (it.box[5] - it.box[2]));
        }
        return b;
      },
      [](ElementBounds a, const ElementBounds& b) {
        for (int k = 0; k < 3; ++k) {
          a.lo[k] = std::min(a.lo[k], b.lo[k]);
          a.hi[k] = std::max(a.hi[k], b.hi[k]);
        }
        return a;
      });
  m_lo = bounds.lo;
  m_hi = bounds.hi;
  // The voxel: the mean cube root of the elements' box volumes, summed in canonical order (a
  // serial sum: the same bits under any thread count)
  double h = 0.0;
  for (const double r : root) h += r;
  m_spacing = Vec3(h / static_cast<double>(n));
  return centroid_x;
}

void MeshLayout::place_grid() {
  const double cap = 4.0 * static_cast<double>(m_element.size()) + 64.0;
  double h = m_spacing.x;
  for (;;) {
    double voxels = 1.0;
    for (int a = 0; a < 3; ++a) {
      m_dims[a] = std::max<std::int64_t>(2, std::llround((m_hi[a] - m_lo[a]) / h) + 1);
      voxels *= static_cast<double>(m_dims[a] - 1);
    }
    if (voxels <= cap) break;
    h *= std::cbrt(voxels / cap) * 1.0001;
  }
  for (int a = 0; a < 3; ++a) m_spacing[a] = (m_hi[a] - m_lo[a]) / static_cast<double>(m_dims[a] - 1);
}

void MeshLayout::build_location(const std::vector<double>& centroid_x) {
  const std::size_t n = m_element.size();
  const double budget = 64.0 * static_cast<double>(n) + 4096.0;
  // The location cell of coordinate x along axis a, for the current cell size (monotone in x)
  const auto loc_cell = [&](int a, double x) {
    const double q = std::floor((x - m_loc_lo[a]) * m_loc_inv[a]);
    return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::clamp(q, -1.0, 9e18)), 0, m_loc_n[a] - 1);
  };
  // The location cells of element e along axis a
  const auto span = [&](std::size_t e, int a, std::int64_t* c0, std::int64_t* c1) {
    *c0 = loc_cell(a, m_box[6 * e + a]);
    *c1 = loc_cell(a, m_box[6 * e + 3 + a]);
  };
  for (double scale = 1.0;; scale *= 2.0) {
    for (int a = 0; a < 3; ++a) {
      const double edge = m_spacing[a] * scale;
      m_loc_lo[a] = m_lo[a] - 0.5 * m_spacing[a];
      m_loc_inv[a] = 1.0 / edge;
      m_loc_n[a] = static_cast<std::int64_t>(std::floor((m_hi[a] + 0.5 * m_spacing[a] - m_loc_lo[a]) / edge)) + 1;
    }
    // The (element, cell) pairs, an integer sum over threads; chunks stop once it is over
    // the budget (whether it is over does not depend on the split)
    std::atomic<std::uint64_t> pairs{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), [&](const auto& r) {
      if (static_cast<double>(pairs.load(std::memory_order_relaxed)) > budget) return;
      std::uint64_t mine = 0;
      for (std::size_t e = r.begin(); e != r.end(); ++e) {
        std::uint64_t p = 1;
        for (int a = 0; a < 3; ++a) {
          std::int64_t c0, c1;
          span(e, a, &c0, &c1);
          p *= static_cast<std::uint64_t>(c1 - c0 + 1);
        }
        mine += p;
      }
      pairs.fetch_add(mine, std::memory_order_relaxed);
    });
    if (static_cast<double>(pairs.load()) <= budget) break;
  }
  // Lists: counts, prefix sums, fill in canonical order. Over threads by slabs of location
  // cells along x, each slab counting and filling only its own cells, its elements visited in
  // canonical order: every list is in canonical order, the same bits under any thread count
  // or slab count, with no atomics. The elements are sorted by centroid x first, so the
  // elements that reach a slab are a contiguous run of the canonical order (slab_runs).
  const std::int64_t cells = m_loc_n[0] * m_loc_n[1] * m_loc_n[2];
  m_first.assign(static_cast<std::size_t>(cells) + 1, 0);
  const auto each_cell = [&](std::size_t e, std::int64_t i0, std::int64_t i1, auto&& fn) {
    std::int64_t c0[3], c1[3];
    for (int a = 0; a < 3; ++a) span(e, a, &c0[a], &c1[a]);
    c0[0] = std::max(c0[0], i0);
    c1[0] = std::min(c1[0], i1 - 1);
    for (std::int64_t k = c0[2]; k <= c1[2]; ++k)
      for (std::int64_t j = c0[1]; j <= c1[1]; ++j)
        for (std::int64_t i = c0[0]; i <= c1[0]; ++i)
          fn(static_cast<std::size_t>((k * m_loc_n[1] + j) * m_loc_n[0] + i));
  };
  const std::vector<SlabRun> slabs = slab_runs(n, centroid_x, m_loc_n[0], loc_cell, span);
  const auto over_slabs = [&](auto&& body) {
    tbb::parallel_for(std::size_t{0}, slabs.size(), [&](std::size_t s) {
      const SlabRun& run = slabs[s];
      for (std::size_t e = run.first; e < run.last; ++e)
        each_cell(e, run.i0, run.i1, [&](std::size_t c) { body(e, c); });
    });
  };
  over_slabs([&](std::size_t, std::size_t c) { ++m_first[c + 1]; });
  for (std::size_t c = 0; c < static_cast<std::size_t>(cells); ++c) m_first[c + 1] += m_first[c];
  m_list.resize(m_first.back());
  std::vector<std::uint64_t> next(m_first.begin(), m_first.end() - 1);
  over_slabs([&](std::size_t e, std::size_t c) { m_list[next[c]++] = static_cast<std::uint32_t>(e); });
}

MeshFieldView MeshLayout::view(const DomainAccess* domains) const {
  MeshFieldView v;
  if (m_element.empty()) return v;
  v.domain = domains;
  v.element = m_element.data();
  v.box = m_box.data();
  v.first = m_first.data();
  v.list = m_list.data();
  v.origin = m_lo;
  v.spacing = m_spacing;
  v.loc_lo = m_loc_lo;
  v.loc_inv = m_loc_inv;
  for (int a = 0; a < 3; ++a) v.loc_n[a] = m_loc_n[a];
  return v;
}

VolumeGeometry MeshLayout::geometry() const {
  VolumeGeometry g;
  g.origin = m_lo;
  g.spacing = m_spacing;
  g.association = Association::Vertex;
  return g;
}

std::uint64_t MeshLayout::bytes() const {
  std::uint64_t spans = 0;
  {
    const std::lock_guard<std::mutex> lock(m_spans_mutex);
    if (m_spans) spans = m_spans->bytes();
  }
  return m_signature.size() * sizeof(std::int64_t) + m_element.size() * sizeof(MeshElementRef) +
         m_box.size() * sizeof(double) + m_first.size() * sizeof(std::uint64_t) +
         m_list.size() * sizeof(std::uint32_t) + spans;
}

std::size_t MeshLayout::domain_count() const { return m_signature.size() / kSignatureWords; }

std::int64_t MeshLayout::domain_cells(std::size_t d) const { return m_signature[d * kSignatureWords + 5]; }

std::shared_ptr<const MacroSpans> MeshLayout::macro_spans(const MacroGrid& grid) const {
  // Made under the lock: two prepares over one layout at once wait for one build, not two
  const std::lock_guard<std::mutex> lock(m_spans_mutex);
  if (!m_spans || !m_spans->over(grid)) {
    m_spans.reset();  // the old spans freed before the new are made
    m_spans = std::make_shared<const MacroSpans>(*this, grid);
  }
  return m_spans;
}

}  // namespace tessera
