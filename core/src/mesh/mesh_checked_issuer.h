#pragma once
/// MeshCheckedIssuer: how the check functions (mesh_check.cpp, cuda/mesh_device_host.cpp) make
/// the receipt MeshChecked (mesh.h) of the mesh they accepted; nothing else makes one.
#include <tessera/mesh.h>

namespace tessera {

struct MeshCheckedIssuer {
  /// The receipt of `mesh`, checked with its shapes (`shapes`) or its indices only.
  static MeshChecked issue(const Mesh& mesh, bool shapes) {
    MeshChecked c;
    c.m_domains = mesh.domains;
    c.m_device = mesh.device;
    c.m_shapes = shapes;
    return c;
  }
  /// Records the values' totals measured by the same check.
  static void record(MeshChecked& c, const MeshValueTotals& v) {
    c.m_values = v;
    c.m_has_values = true;
  }
};

}  // namespace tessera
