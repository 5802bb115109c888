#pragma once
/// The values' side of a mesh's tables, one element or one value at a time, for the host's
/// build (mesh_tables.cpp, mesh_summary.cpp) and a device's (cuda/mesh_device.h) alike: an
/// element's value range, the macrocells its box meets, one value folded into a range. Host
/// and device code (host_device.h); the same arithmetic in the same order on both, so that
/// the summaries agree bit for bit.
#include <tessera/host_device.h>

#include "mesh/domain_access.h"
#include "mesh/mesh_field_view.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace tessera {

/// Value range of one element (or of the elements meeting one macrocell): finite min / max
/// and bit 0 NaN, bit 1 +Inf, bit 2 -Inf among the values (FieldSummary::Parts' flags).
struct ElementRange {
  double lo = INFINITY, hi = -INFINITY;
  std::uint8_t flags = 0;
};

/// The flag of a value that is not finite (bit 0 NaN, 1 +Inf, 2 -Inf); 0 when finite.
TESSERA_HOST_DEVICE inline std::uint8_t value_flag(double v) {
  if (v != v) return 1;
  if (v == INFINITY) return 2;
  if (v == -INFINITY) return 4;
  return 0;
}

/// Folds value v into r: a flag, or the finite min / max with -0.0 as +0.0 (so that ranges are
/// bit-identical in any order).
TESSERA_HOST_DEVICE inline void add_value(ElementRange& r, double v) {
  const std::uint8_t f = value_flag(v);
  if (f != 0) {
    r.flags |= f;
    return;
  }
  v += 0.0;
  r.lo = r.lo < v ? r.lo : v;
  r.hi = v < r.hi ? r.hi : v;
}

/// The range of element `ref`'s values: its cell value, or its vertices' values.
TESSERA_HOST_DEVICE inline ElementRange element_range(const DomainAccess* domains, const MeshElementRef& ref) {
  const DomainAccess& d = domains[ref.domain];
  ElementRange r;
  if (d.cell_data) {
    add_value(r, d.value(ref.cell));
    return r;
  }
  std::int64_t idx[8];
  d.cell_vertices(ref.cell, idx);
  double v[8] = {};  // (nv >= 1: the fast path's v[0] is a value)
  bool finite = true;
  for (int k = 0; k < d.nv; ++k) {
    v[k] = d.value(idx[k]);
    finite &= (v[k] - v[k]) == 0.0;  // false for NaN and +-Inf
  }
  if (!finite) {
    for (int k = 0; k < d.nv; ++k) add_value(r, v[k]);
    return r;
  }
  // Every value finite (the common case): add_value's min / max without its branches, the
  // same bits (zeros as +0.0, so that equal values are one bit pattern in any order)
  double lo = v[0] + 0.0, hi = lo;
  for (int k = 1; k < d.nv; ++k) {
    const double x = v[k] + 0.0;
    lo = lo < x ? lo : x;
    hi = x < hi ? hi : x;
  }
  r.lo = lo;
  r.hi = hi;
  return r;
}

/// Cell `cell`'s box (lo x, y, z, hi x, y, z): the min / max of its vertices, in their order
/// (MeshLayout's boxes are these).
TESSERA_HOST_DEVICE inline void element_box(const DomainAccess& d, std::int64_t cell, double* box) {
  std::int64_t idx[8];
  d.cell_vertices(cell, idx);
  Vec3 lo(INFINITY), hi(-INFINITY);
  for (int k = 0; k < d.nv; ++k) {
    const Vec3 v = d.vertex(idx[k]);
    for (int a = 0; a < 3; ++a) {
      lo[a] = v[a] < lo[a] ? v[a] : lo[a];
      hi[a] = hi[a] < v[a] ? v[a] : hi[a];
    }
  }
  for (int a = 0; a < 3; ++a) {
    box[a] = lo[a];
    box[3 + a] = hi[a];
  }
}

/// The macrocells over a mesh's grid: `cells` per axis of `edge` voxels of the grid at
/// `origin` with `spacing` (mesh_summary.h).
struct MacroGrid {
  double origin[3] = {0.0, 0.0, 0.0};
  double spacing[3] = {1.0, 1.0, 1.0};
  std::int64_t cells[3] = {1, 1, 1};
  std::int64_t edge = 1;

  /// The macrocell of world coordinate x along axis a, nudged by `pad` voxels, clamped inside.
  TESSERA_HOST_DEVICE std::int64_t cell(int a, double x, double pad) const {
    const double p = (x - origin[a]) / spacing[a] + pad;
    const double c = p < -1.0 ? -1.0 : (p > 9e18 ? 9e18 : p);
    const double q = std::floor(c / static_cast<double>(edge));
    const auto i = static_cast<std::int64_t>(q);
    return i < 0 ? 0 : (i > cells[a] - 1 ? cells[a] - 1 : i);
  }
  /// The macrocells [c0, c1] (per axis, inclusive) that box (lo x, y, z, hi x, y, z), padded by
  /// 1e-6 voxels, meets.
  TESSERA_HOST_DEVICE void span(const double* box, std::int64_t* c0, std::int64_t* c1) const {
    for (int a = 0; a < 3; ++a) {
      c0[a] = cell(a, box[a], -1e-6);
      c1[a] = cell(a, box[3 + a], 1e-6);
    }
  }
};

}  // namespace tessera
