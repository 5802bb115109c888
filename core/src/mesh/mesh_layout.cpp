/// MeshLayout (mesh_layout.h): gather the real elements, sort them canonically, lay the grid
/// over their box and list them per location cell.
#include "mesh/mesh_layout.h"

#include <tessera/render.h>

#include "mesh/element_range.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tessera {
namespace {

/// One real element while building: where it is, for the canonical order.
struct Item {
  Vec3 centroid;
  double box[6];
  MeshElementRef ref;
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

}  // namespace

MeshLayout::MeshLayout(const Mesh& mesh, const std::vector<DomainAccess>& domains) {
  for (const MeshDomain& d : mesh.domains) append_signature(d, m_signature);
  gather(domains, mesh);
  place_grid();
  build_location();
}

bool mesh_layout_fits(const MeshLayout& layout, const Mesh& mesh) { return layout.fits(mesh); }

bool MeshLayout::fits(const Mesh& mesh) const {
  std::vector<std::int64_t> s;
  s.reserve(m_signature.size());
  for (const MeshDomain& d : mesh.domains) append_signature(d, s);
  return s == m_signature;
}

void MeshLayout::gather(const std::vector<DomainAccess>& domains, const Mesh& mesh) {
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
  m_lo = Vec3(INFINITY);
  m_hi = Vec3(-INFINITY);
  for (std::size_t e = 0; e < n; ++e) {
    const Item& it = items[e];
    m_element[e] = it.ref;
    for (int a = 0; a < 3; ++a) {
      m_box[6 * e + a] = it.box[a];
      m_box[6 * e + 3 + a] = it.box[3 + a];
      m_lo[a] = std::min(m_lo[a], it.box[a]);
      m_hi[a] = std::max(m_hi[a], it.box[3 + a]);
    }
  }
  // The voxel: the mean cube root of the elements' box volumes, summed in canonical order
  double h = 0.0;
  for (const Item& it : items)
    h += std::cbrt((it.box[3] - it.box[0]) * (it.box[4] - it.box[1]) * (it.box[5] - it.box[2]));
  m_spacing = Vec3(h / static_cast<double>(n));
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

void MeshLayout::build_location() {
  const std::size_t n = m_element.size();
  const double budget = 64.0 * static_cast<double>(n) + 4096.0;
  // The location cells of element e along axis a, for the current cell size
  const auto span = [&](std::size_t e, int a, std::int64_t* c0, std::int64_t* c1) {
    const auto cell = [&](double x) {
      const double q = std::floor((x - m_loc_lo[a]) * m_loc_inv[a]);
      return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::clamp(q, -1.0, 9e18)), 0, m_loc_n[a] - 1);
    };
    *c0 = cell(m_box[6 * e + a]);
    *c1 = cell(m_box[6 * e + 3 + a]);
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
  // Lists: count, prefix sums, fill in canonical order
  const std::int64_t cells = m_loc_n[0] * m_loc_n[1] * m_loc_n[2];
  m_first.assign(static_cast<std::size_t>(cells) + 1, 0);
  const auto each_cell = [&](std::size_t e, auto&& fn) {
    std::int64_t c0[3], c1[3];
    for (int a = 0; a < 3; ++a) span(e, a, &c0[a], &c1[a]);
    for (std::int64_t k = c0[2]; k <= c1[2]; ++k)
      for (std::int64_t j = c0[1]; j <= c1[1]; ++j)
        for (std::int64_t i = c0[0]; i <= c1[0]; ++i)
          fn(static_cast<std::size_t>((k * m_loc_n[1] + j) * m_loc_n[0] + i));
  };
  for (std::size_t e = 0; e < n; ++e) each_cell(e, [&](std::size_t c) { ++m_first[c + 1]; });
  for (std::size_t c = 0; c < static_cast<std::size_t>(cells); ++c) m_first[c + 1] += m_first[c];
  m_list.resize(m_first.back());
  std::vector<std::uint64_t> next(m_first.begin(), m_first.end() - 1);
  for (std::size_t e = 0; e < n; ++e)
    each_cell(e, [&](std::size_t c) { m_list[next[c]++] = static_cast<std::uint32_t>(e); });
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
  return m_signature.size() * sizeof(std::int64_t) + m_element.size() * sizeof(MeshElementRef) +
         m_box.size() * sizeof(double) + m_first.size() * sizeof(std::uint64_t) + m_list.size() * sizeof(std::uint32_t);
}

}  // namespace tessera
