/// MeshTables::build (mesh_tables.h): the layout (built, or reused); the values' totals.
#include "mesh/mesh_tables.h"

#include "mesh/geometry_hash.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tessera {
void MeshTables::build(const Mesh& mesh, std::shared_ptr<const MeshLayout> reuse) {
  bind(mesh);
  m_reused = reuse && reuse->fits(mesh);
  m_layout = m_reused ? std::move(reuse) : std::make_shared<const MeshLayout>(mesh, m_domain);
  // The elements' value ranges are mesh_summary's (in the input's order, over the layout's
  // kept macrocell spans). A reused layout whose element is a ghost now (a broken promise: the
  // geometry hash covers the ghost masks) is refused: a ghost's indices are never checked, so
  // neither the summary nor the kernels may read them. A new layout has no ghost by its build
  if (m_reused && has_ghost_masks(mesh)) refuse_new_ghosts(mesh);
}

void MeshTables::refuse_new_ghosts(const Mesh& mesh) const {
  const std::size_t n = m_layout->element_count();
  std::atomic<std::size_t> ghost{n};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), [&](const auto& r) {
    for (std::size_t e = r.begin(); e != r.end(); ++e) {
      const MeshElementRef& ref = m_layout->element(e);
      if (!mesh.domains[static_cast<std::size_t>(ref.domain)].ghosts.is_ghost(ref.cell)) continue;
      std::size_t seen = ghost.load(std::memory_order_relaxed);
      while (e < seen && !ghost.compare_exchange_weak(seen, e, std::memory_order_relaxed)) {
      }
    }
  });
  if (ghost.load() == n) return;
  const MeshElementRef& ref = m_layout->element(ghost.load());
  throw std::invalid_argument("mesh domain " + std::to_string(ref.domain) + ": element " + std::to_string(ref.cell) +
                              " is a ghost now but was real when the mesh's lookup structure was built: the "
                              "geometry is not the one promised unchanged");
}

void MeshTables::build_on_device(const Mesh& mesh, std::shared_ptr<const MeshLayout> layout) {
  bind(mesh);
  m_layout = std::move(layout);
  m_reused = true;
  m_on_device = true;
}

void MeshTables::bind(const Mesh& mesh) {
  m_on_device = false;
  m_domain.clear();
  m_arrays.clear();
  m_value_offset.assign(1, 0);
  for (const MeshDomain& d : mesh.domains) {
    m_domain.push_back(DomainAccess::of(d));
    m_value_offset.push_back(m_value_offset.back() + d.field.count);
    DomainArrays& a = m_arrays.emplace_back();
    for (int s = 0; s < kMeshArraySlots; ++s) {
      a.span[static_cast<std::size_t>(s)] = mesh_array(d, static_cast<MeshArraySlot>(s));
      a.device_copy[static_cast<std::size_t>(s)] = d.device_copy[s];
    }
  }
}

namespace {

/// NaN count and range of some values: min / max (zeros as +0.0) and an integer sum, so that
/// any split of the values over threads gives the same bits.
struct ValueTally {
  std::uint64_t nan = 0;
  ElementRange all;
  void merge(const ValueTally& o) {
    nan += o.nan;
    all.lo = std::min(all.lo, o.all.lo);
    all.hi = std::max(all.hi, o.all.hi);
    all.flags |= o.all.flags;
  }
};

}  // namespace

MeshTables::ValueTotals MeshTables::value_totals(std::uint64_t v0, std::uint64_t v1) const {
  ValueTally total;
  for (std::size_t i = 0; i < m_domain.size(); ++i) {
    const auto first = static_cast<std::uint64_t>(m_value_offset[i]),
               last = static_cast<std::uint64_t>(m_value_offset[i + 1]);
    const std::uint64_t lo = std::max(v0, first), hi = std::min(v1, last);
    if (lo >= hi) continue;
    const DomainAccess& d = m_domain[i];
    total.merge(tbb::parallel_reduce(
        tbb::blocked_range<std::int64_t>(static_cast<std::int64_t>(lo - first), static_cast<std::int64_t>(hi - first),
                                         16384),
        ValueTally{},
        [&](const auto& r, ValueTally t) {
          for (std::int64_t v = r.begin(); v != r.end(); ++v) {
            const double x = d.value(v);
            t.nan += std::isnan(x) ? 1 : 0;
            add_value(t.all, x);
          }
          return t;
        },
        [](ValueTally a, const ValueTally& b) {
          a.merge(b);
          return a;
        }));
  }
  ValueTotals out;
  out.nan = total.nan;
  out.count = v1 > v0 ? v1 - v0 : 0;
  out.lo = total.all.lo;
  out.hi = total.all.hi;
  return out;
}

MeshFieldView MeshTables::view() const { return m_layout ? m_layout->view(m_domain.data()) : MeshFieldView{}; }

std::uint64_t MeshTables::bytes() const {
  return m_domain.size() * (sizeof(DomainAccess) + sizeof(DomainArrays)) + (m_layout ? m_layout->bytes() : 0);
}

}  // namespace tessera
