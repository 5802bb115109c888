#pragma once
/// DomainAccess: how the build and the kernels read one mesh domain's arrays in place
/// (mesh.h): a vertex's position, a cell's vertex indices (a curvilinear cell's from its
/// i, j, k; an unstructured one's from the connectivity) and a value, each dtype read per
/// load. Trivially copyable; points into the caller's arrays (valid while they are). The
/// readers are host and device code (host_device.h).
#include <tessera/brick_cache.h>
#include <tessera/host_device.h>
#include <tessera/math.h>
#include <tessera/mesh.h>

#include <cstdint>
#include <type_traits>

namespace tessera {

struct DomainAccess {
  const unsigned char* x = nullptr;
  const unsigned char* y = nullptr;
  const unsigned char* z = nullptr;
  std::int64_t coord_stride = 0;
  bool coord_f64 = true;
  std::int64_t dims[3] = {0, 0, 0};  ///< curvilinear vertices per axis; 0: unstructured
  const unsigned char* conn = nullptr;
  bool index64 = false;
  int nv = 8;  ///< vertices per cell
  Shape shape = Shape::Hex;
  const unsigned char* values = nullptr;
  DType value_dtype = DType::Float32;
  std::int64_t value_stride = 0;
  bool cell_data = false;

  static DomainAccess of(const MeshDomain& d) {
    DomainAccess a;
    a.x = static_cast<const unsigned char*>(d.coords.x);
    a.y = static_cast<const unsigned char*>(d.coords.y);
    a.z = static_cast<const unsigned char*>(d.coords.z);
    a.coord_stride = d.coords.byte_stride;
    a.coord_f64 = d.coords.dtype == DType::Float64;
    for (int i = 0; i < 3; ++i) a.dims[i] = d.structured() ? d.dims[i] : 0;
    a.conn = static_cast<const unsigned char*>(d.connectivity);
    a.index64 = d.index_type == IndexType::Int64;
    a.shape = d.cell_shape();
    a.nv = shape_vertex_count(a.shape);
    a.values = static_cast<const unsigned char*>(d.field.data);
    a.value_dtype = d.field.dtype;
    a.value_stride = d.field.byte_stride;
    a.cell_data = d.field.association == Association::Cell;
    return a;
  }

  TESSERA_HOST_DEVICE bool structured() const { return dims[0] != 0; }

  TESSERA_HOST_DEVICE double coord(const unsigned char* base, std::int64_t v) const {
    const unsigned char* p = base + v * coord_stride;
    if (coord_f64) {
      double c;
      __builtin_memcpy(&c, p, sizeof c);
      return c;
    }
    float c;
    __builtin_memcpy(&c, p, sizeof c);
    return static_cast<double>(c);
  }
  TESSERA_HOST_DEVICE Vec3 vertex(std::int64_t v) const { return Vec3(coord(x, v), coord(y, v), coord(z, v)); }

  /// The raw connectivity entry `corner` of unstructured cell `cell` (unchecked).
  TESSERA_HOST_DEVICE std::int64_t conn_entry(std::int64_t cell, int corner) const {
    const std::int64_t e = cell * nv + corner;
    if (index64) {
      std::int64_t i;
      __builtin_memcpy(&i, conn + e * 8, sizeof i);
      return i;
    }
    std::int32_t i;
    __builtin_memcpy(&i, conn + e * 4, sizeof i);
    return i;
  }

  /// The nv vertex indices of `cell` in VTK order (a curvilinear cell's hex of vertices
  /// (i..i+1, j..j+1, k..k+1), cell index i fastest over dims - 1).
  TESSERA_HOST_DEVICE void cell_vertices(std::int64_t cell, std::int64_t* idx) const {
    if (!structured()) {
      for (int c = 0; c < nv; ++c) idx[c] = conn_entry(cell, c);
      return;
    }
    const std::int64_t cx = dims[0] - 1, cy = dims[1] - 1;
    const std::int64_t i = cell % cx, j = (cell / cx) % cy, k = cell / (cx * cy);
    const std::int64_t base = (k * dims[1] + j) * dims[0] + i, sj = dims[0], sk = dims[0] * dims[1];
    const std::int64_t off[8] = {0, 1, 1 + sj, sj, sk, 1 + sk, 1 + sj + sk, sj + sk};
    for (int c = 0; c < 8; ++c) idx[c] = base + off[c];
  }

  TESSERA_HOST_DEVICE double value(std::int64_t e) const {
    return detail::load_as_double(value_dtype, values + e * value_stride);
  }
};
static_assert(std::is_trivially_copyable_v<DomainAccess>);

}  // namespace tessera
