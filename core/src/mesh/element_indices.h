#pragma once
/// element_index_fault: whether one cell's vertices can be read and placed: each vertex index
/// inside the domain's vertex count and each vertex's coordinates finite. The part of
/// check_mesh (mesh_check.cpp) a kernel needs to read inside a domain's arrays; shapes are
/// not looked at. Host and device code (host_device.h), so that a device can check arrays it
/// holds with the host's rule.
#include <tessera/host_device.h>
#include <tessera/math.h>

#include "mesh/domain_access.h"

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace tessera {

/// Fills idx[0..a.nv) with cell `cell`'s vertex indices and v[] with the vertices read so far;
/// returns the first corner whose index is outside [0, `vertices`) or whose vertex has a NaN
/// or Inf coordinate (v[k] read only when its index is inside), or -1 when there is none.
TESSERA_HOST_DEVICE inline int element_index_fault(const DomainAccess& a, std::int64_t cell, std::int64_t vertices,
                                                   std::int64_t* idx, Vec3* v) {
  a.cell_vertices(cell, idx);
  for (int k = 0; k < a.nv; ++k) {
    if (!(idx[k] >= 0 && idx[k] < vertices)) return k;
    v[k] = a.vertex(idx[k]);
    if (!(std::isfinite(v[k].x) && std::isfinite(v[k].y) && std::isfinite(v[k].z))) return k;
  }
  return -1;
}

/// Throws check_mesh's std::invalid_argument for cell `cell` of domain `domain` whose corner
/// `corner` element_index_fault named: its `index` outside [0, `vertices`), or its vertex `v`
/// not finite. Host code (mesh_check.cpp).
[[noreturn]] void throw_index_fault(std::size_t domain, std::int64_t cell, int corner, std::int64_t index,
                                    std::int64_t vertices, const Vec3& v);

}  // namespace tessera
