/// MeshTables::build (mesh_tables.h): the layout (built, or reused), then the values' ranges.
#include "mesh/mesh_tables.h"

#include <algorithm>
#include <cmath>

namespace tessera {
void MeshTables::build(const Mesh& mesh, std::shared_ptr<const MeshLayout> reuse) {
  bind(mesh);
  m_reused = reuse && reuse->fits(mesh);
  m_layout = m_reused ? std::move(reuse) : std::make_shared<const MeshLayout>(mesh, m_domain);
  // Each element's value range, in the layout's order
  const std::size_t n = m_layout->element_count();
  m_range.assign(n, ElementRange{});
  for (std::size_t e = 0; e < n; ++e) m_range[e] = element_range(m_domain.data(), m_layout->element(e));
  count_values(mesh);
}

void MeshTables::build_on_device(const Mesh& mesh, std::shared_ptr<const MeshLayout> layout) {
  bind(mesh);
  m_layout = std::move(layout);
  m_reused = true;
  m_on_device = true;
  m_range.clear();
  m_nan = m_values = 0;
  m_vmin = INFINITY;
  m_vmax = -INFINITY;
}

void MeshTables::bind(const Mesh& mesh) {
  m_on_device = false;
  m_domain.clear();
  m_arrays.clear();
  for (const MeshDomain& d : mesh.domains) {
    m_domain.push_back(DomainAccess::of(d));
    DomainArrays& a = m_arrays.emplace_back();
    for (int s = 0; s < kMeshArraySlots; ++s) {
      a.span[static_cast<std::size_t>(s)] = mesh_array(d, static_cast<MeshArraySlot>(s));
      a.device_copy[static_cast<std::size_t>(s)] = d.device_copy[s];
    }
  }
}

void MeshTables::count_values(const Mesh& mesh) {
  m_nan = m_values = 0;
  ElementRange all;
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const DomainAccess& d = m_domain[i];
    const std::int64_t count = mesh.domains[i].field.count;
    for (std::int64_t v = 0; v < count; ++v) {
      const double x = d.value(v);
      m_nan += std::isnan(x) ? 1 : 0;
      add_value(all, x);
    }
    m_values += static_cast<std::uint64_t>(count);
  }
  m_vmin = all.lo;
  m_vmax = all.hi;
}

MeshFieldView MeshTables::view() const { return m_layout ? m_layout->view(m_domain.data()) : MeshFieldView{}; }

std::uint64_t MeshTables::bytes() const {
  return m_domain.size() * (sizeof(DomainAccess) + sizeof(DomainArrays)) + m_range.size() * sizeof(ElementRange) +
         (m_layout ? m_layout->bytes() : 0);
}

}  // namespace tessera
