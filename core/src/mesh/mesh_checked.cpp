/// MeshChecked::covers (mesh.h): the receipt's descriptors against a mesh's, field by field.
#include <tessera/mesh.h>

namespace tessera {
namespace {

bool same(const MeshCoords& a, const MeshCoords& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z && a.dtype == b.dtype && a.byte_stride == b.byte_stride &&
         a.count == b.count;
}

bool same(const MeshField& a, const MeshField& b) {
  return a.data == b.data && a.dtype == b.dtype && a.byte_stride == b.byte_stride && a.count == b.count &&
         a.association == b.association;
}

bool same(const MeshGhosts& a, const MeshGhosts& b) {
  return a.data == b.data && a.byte_stride == b.byte_stride && a.count == b.count;
}

/// Whether a and b are the same domain, or (`values`) the same but for the field's data.
bool same(const MeshDomain& a, const MeshDomain& b, bool values = false) {
  for (int i = 0; i < 3; ++i)
    if (a.dims[i] != b.dims[i]) return false;
  for (int s = 0; s < kMeshArraySlots; ++s)
    if (a.device_copy[s] != b.device_copy[s]) return false;
  MeshField field = b.field;
  if (values) field.data = a.field.data;
  return same(a.coords, b.coords) && a.shape == b.shape && a.connectivity == b.connectivity &&
         a.index_type == b.index_type && a.ncells == b.ncells && same(a.field, field) && same(a.ghosts, b.ghosts);
}

}  // namespace

MeshChecked MeshChecked::with_new_values(const Mesh& mesh) const {
  if (m_domains.empty() || mesh.device != m_device || mesh.domains.size() != m_domains.size()) return {};
  for (std::size_t i = 0; i < m_domains.size(); ++i)
    if (!same(m_domains[i], mesh.domains[i], true)) return {};
  MeshChecked c;
  c.m_domains = mesh.domains;
  c.m_device = m_device;
  c.m_shapes = m_shapes;
  return c;
}

bool MeshChecked::covers(const Mesh& mesh, bool shapes) const {
  if (m_domains.empty() || mesh.device != m_device || (shapes && !m_shapes) || mesh.domains.size() != m_domains.size())
    return false;
  for (std::size_t i = 0; i < m_domains.size(); ++i)
    if (!same(m_domains[i], mesh.domains[i])) return false;
  return true;
}

}  // namespace tessera
