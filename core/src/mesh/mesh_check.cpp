/// check_mesh (mesh.h): every domain's arrays, then every element, in one pass each.
#include <tessera/host_readable.h>
#include <tessera/mesh.h>
#include <tessera/number_text.h>

#include "mesh/domain_access.h"
#include "mesh/element_geometry.h"
#include "mesh/element_indices.h"
#include "mesh/mesh_checked_issuer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace tessera {
namespace {

/// Throws std::invalid_argument "mesh domain D: what" when !ok.
struct DomainCheck {
  std::size_t domain;
  void require(bool ok, const std::string& what) const {
    if (!ok) throw std::invalid_argument("mesh domain " + std::to_string(domain) + ": " + what);
  }
  void require(bool ok, std::int64_t element, const std::string& what) const {
    require(ok, "element " + std::to_string(element) + ": " + what);
  }
};

bool valid_dtype(DType t) {
  return static_cast<int>(t) >= 0 && static_cast<int>(t) <= static_cast<int>(DType::Float64);
}

/// True when count elements of `size` bytes, byte_stride apart, span an int64 byte range.
bool span_fits(std::int64_t count, std::int64_t byte_stride, std::int64_t size) {
  std::int64_t bytes = 0;
  return count <= 0 ||
         (!__builtin_mul_overflow(count - 1, byte_stride, &bytes) && !__builtin_add_overflow(bytes, size, &bytes));
}

void check_coords(const DomainCheck& c, const MeshCoords& x) {
  c.require(x.dtype == DType::Float32 || x.dtype == DType::Float64,
            "coordinates must be float32 or float64, not " +
                std::string(valid_dtype(x.dtype) ? dtype_name(x.dtype) : "an unknown dtype"));
  const auto size = static_cast<std::int64_t>(dtype_size(x.dtype));
  c.require(x.count >= 0, "vertex count " + std::to_string(x.count) + " is negative");
  c.require(x.byte_stride >= size, "coordinate byte_stride " + std::to_string(x.byte_stride) +
                                       " is below the coordinate size " + std::to_string(size));
  c.require(span_fits(x.count, x.byte_stride, size),
            std::to_string(x.count) + " vertices x byte_stride " + std::to_string(x.byte_stride) + " overflow int64");
  c.require(x.count == 0 || (x.x && x.y && x.z), "a coordinate array (x, y or z) is null");
}

/// The domain's cell count, its topology checked.
std::int64_t check_topology(const DomainCheck& c, const MeshDomain& d) {
  if (d.structured()) {
    std::int64_t n = 1;
    for (int a = 0; a < 3; ++a) {
      c.require(d.dims[a] >= 2, "curvilinear dims[" + std::to_string(a) + "] = " + std::to_string(d.dims[a]) +
                                    " (vertices per axis) must be >= 2");
      c.require(!__builtin_mul_overflow(n, d.dims[a], &n), "curvilinear dims overflow int64");
    }
    c.require(n == d.coords.count, "curvilinear dims " + std::to_string(d.dims[0]) + "x" + std::to_string(d.dims[1]) +
                                       "x" + std::to_string(d.dims[2]) + " need " + std::to_string(n) +
                                       " vertices, the coordinates have " + std::to_string(d.coords.count));
    return d.cell_count();
  }
  const int s = static_cast<int>(d.shape);
  c.require(s >= 0 && s <= static_cast<int>(Shape::Pyramid), "unknown element shape " + std::to_string(s));
  c.require(d.shape == Shape::Hex || d.shape == Shape::Tet,
            std::string(shape_name(d.shape)) + " elements are not supported yet (hex and tet are)");
  c.require(d.index_type == IndexType::Int32 || d.index_type == IndexType::Int64,
            "unknown connectivity index type " + std::to_string(static_cast<int>(d.index_type)));
  c.require(d.ncells >= 0, "element count " + std::to_string(d.ncells) + " is negative");
  const std::int64_t isize = d.index_type == IndexType::Int64 ? 8 : 4;
  std::int64_t entries = 0;
  c.require(
      !__builtin_mul_overflow(d.ncells, shape_vertex_count(d.shape), &entries) && span_fits(entries, isize, isize),
      std::to_string(d.ncells) + " elements x " + std::to_string(shape_vertex_count(d.shape)) +
          " indices overflow int64");
  c.require(d.ncells == 0 || d.connectivity, "the connectivity array is null");
  return d.ncells;
}

void check_field(const DomainCheck& c, const MeshDomain& d, std::int64_t cells) {
  const MeshField& f = d.field;
  c.require(valid_dtype(f.dtype), "unknown field dtype " + std::to_string(static_cast<int>(f.dtype)));
  c.require(f.association == Association::Vertex || f.association == Association::Cell,
            "field association " + std::to_string(static_cast<int>(f.association)) + " is neither vertex nor cell");
  const bool cell = f.association == Association::Cell;
  const std::int64_t want = cell ? cells : d.coords.count;
  c.require(f.count == want, "the field has " + std::to_string(f.count) + " values, " + (cell ? "cell" : "vertex") +
                                 " data needs " + std::to_string(want) + " (one per " + (cell ? "cell" : "vertex") +
                                 ")");
  const auto size = static_cast<std::int64_t>(dtype_size(f.dtype));
  c.require(f.byte_stride >= size,
            "field byte_stride " + std::to_string(f.byte_stride) + " is below the value size " + std::to_string(size));
  c.require(span_fits(f.count, f.byte_stride, size),
            std::to_string(f.count) + " values x byte_stride " + std::to_string(f.byte_stride) + " overflow int64");
  c.require(f.count == 0 || f.data, "the field's data is null");
  const MeshGhosts& g = d.ghosts;
  if (!g.data) return;
  c.require(g.count == cells, "the ghost mask has " + std::to_string(g.count) + " entries, the domain " +
                                  std::to_string(cells) + " cells");
  c.require(g.byte_stride >= 1, "ghost mask byte_stride " + std::to_string(g.byte_stride) + " must be >= 1");
  c.require(span_fits(g.count, g.byte_stride, 1), std::to_string(g.count) + " ghost entries x byte_stride " +
                                                      std::to_string(g.byte_stride) + " overflow int64");
}

std::string point_text(const Vec3& p) {
  return "(" + short_number(p.x) + ", " + short_number(p.y) + ", " + short_number(p.z) + ")";
}

/// The diagonal of the element's bounding box (a size for the relative tests; at least its
/// longest edge).
double element_size(const Vec3* v, int n) {
  Vec3 lo = v[0], hi = v[0];
  for (int i = 1; i < n; ++i) {
    lo = glm::min(lo, v[i]);
    hi = glm::max(hi, v[i]);
  }
  return glm::length(hi - lo);
}

/// The hex's shape: corner Jacobians of one sign (`*sign`: +1 or -1, 0 = take this cell's)
/// and above 1e-12 L^3, and Newton's inverse at interior points. "" when sound.
std::string hex_fault(const Vec3* v, int* sign) {
  const double L = element_size(v, 8), tiny = 1e-12 * L * L * L;
  if (*sign == 0) *sign = hex_corner_jacobian(v, 0) < 0.0 ? -1 : 1;
  for (int c = 0; c < 8; ++c) {
    const double J = hex_corner_jacobian(v, c) * *sign;
    if (!(J > tiny))
      return (J < -tiny ? "inverted (the Jacobian at vertex " : "degenerate (the Jacobian at vertex ") +
             std::to_string(c) + " is " + short_number(J * *sign) + ", element size " + short_number(L) + ")";
  }
  static constexpr double kTest[3][3] = {{0.5, 0.5, 0.5}, {0.1, 0.2, 0.3}, {0.9, 0.8, 0.7}};
  for (const auto& r0 : kTest) {
    double r[3];
    const bool ok = hex_inverse(v, hex_map(v, r0), r);
    if (!ok || std::max({std::fabs(r[0] - r0[0]), std::fabs(r[1] - r0[1]), std::fabs(r[2] - r0[2])}) > 1e-8)
      return "degenerate (Newton's method does not invert its trilinear map to 1e-10 of its size)";
  }
  return "";
}

std::string tet_fault(const Vec3* v) {
  const double L = element_size(v, 4), V = tet_volume6(v), tiny = 1e-12 * L * L * L;
  if (V > tiny) return "";
  return std::string(V < -tiny ? "inverted" : "degenerate") + " (six times its signed volume is " + short_number(V) +
         ", element size " + short_number(L) + ")";
}

/// Cell e's vertex indices in range and its vertices finite (element_indices.h), read into
/// idx and v; else throws naming the element and the corner.
void check_indices(const DomainCheck& c, const MeshDomain& d, const DomainAccess& a, std::int64_t e, std::int64_t* idx,
                   Vec3* v) {
  const int k = element_index_fault(a, e, d.coords.count, idx, v);
  if (k >= 0) throw_index_fault(c.domain, e, k, idx[k], d.coords.count, v[k]);
}

/// Cell e's shape fault ("" when sound) for a hex's orientation `sign` (+1 or -1).
std::string shape_fault(const DomainAccess& a, const Vec3* v, int sign) {
  return a.shape == Shape::Tet ? tet_fault(v) : hex_fault(v, &sign);
}

/// The orientation every hex of `d` must share: +1 for unstructured cells (VTK's order); a
/// curvilinear grid's first real cell's (either handedness, the same throughout).
int orientation(const MeshDomain& d, const DomainAccess& a, std::int64_t cells) {
  if (!d.structured()) return 1;
  std::int64_t e = 0;
  while (e < cells && d.ghosts.is_ghost(e)) ++e;
  if (e == cells) return 1;
  std::int64_t idx[8];
  Vec3 v[8];
  if (element_index_fault(a, e, d.coords.count, idx, v) >= 0) return 1;  // cell e is the first fault
  return hex_corner_jacobian(v, 0) < 0.0 ? -1 : 1;
}

/// The lowest real cell whose indices, vertices or (`shapes`) shape fail, or `cells`: the
/// cells in parallel (TBB), each chunk in order and stopping past the lowest fault found so
/// far, so that the answer is the lowest whatever the threads do.
std::int64_t first_fault(const MeshDomain& d, const DomainAccess& a, std::int64_t cells, bool shapes, int sign) {
  std::atomic<std::int64_t> first{cells};
  tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, cells, 2048), [&](const auto& r) {
    std::int64_t idx[8];
    Vec3 v[8];
    for (std::int64_t e = r.begin(); e != r.end() && e < first.load(std::memory_order_relaxed); ++e) {
      if (d.ghosts.is_ghost(e)) continue;
      if (element_index_fault(a, e, d.coords.count, idx, v) < 0 && (!shapes || shape_fault(a, v, sign).empty()))
        continue;
      std::int64_t seen = first.load(std::memory_order_relaxed);
      while (e < seen && !first.compare_exchange_weak(seen, e, std::memory_order_relaxed)) {
      }
      return;
    }
  });
  return first.load();
}

/// Every real cell: indices in range, finite vertices, a sound shape (`shapes`) or not looked
/// at; throws for the lowest faulty cell, in the words of a check of that cell alone.
void check_cells(const DomainCheck& c, const MeshDomain& d, std::int64_t cells, bool shapes) {
  const DomainAccess a = DomainAccess::of(d);
  const int sign = orientation(d, a, cells);
  const std::int64_t e = first_fault(d, a, cells, shapes, sign);
  if (e == cells) return;
  std::int64_t idx[8];
  Vec3 v[8];
  check_indices(c, d, a, e, idx, v);
  const std::string fault = shape_fault(a, v, sign);
  c.require(fault.empty(), e, std::string(shape_name(a.shape)) + " is " + fault);
}

/// check_mesh_arrays, then every domain's real cells (check_cells); throws when no cell is real.
void check_all_cells(const Mesh& mesh, bool shapes) {
  check_mesh_arrays(mesh);
  std::int64_t real = 0;
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const MeshDomain& d = mesh.domains[i];
    const std::int64_t cells = d.cell_count();
    check_cells(DomainCheck{i}, d, cells, shapes);
    for (std::int64_t e = 0; e < cells; ++e) real += !d.ghosts.is_ghost(e);
  }
  if (real == 0) throw std::invalid_argument("mesh: no real (non-ghost) cell in any domain");
}

/// Each array's memory readable where it is read (the descriptors checked): freed, unmapped
/// or device memory is named here, not met as a fault (unreadable_byte: 64 probes).
void check_memory(const DomainCheck& c, const MeshDomain& d) {
  for (int s = 0; s < kMeshArraySlots; ++s) {
    const MeshArraySpan a = mesh_array(d, static_cast<MeshArraySlot>(s));
    if (!a.data) continue;
    const auto bytes = static_cast<std::size_t>(a.bytes);
    const auto bad = unreadable_byte(a.data, bytes);
    if (!bad) continue;
    char where[32];
    std::snprintf(where, sizeof where, "%p", a.data);
    c.require(false, std::string(a.name) + " at " + where + " is not readable host memory: byte " +
                         std::to_string(*bad) + " of its " + std::to_string(bytes) +
                         " bytes cannot be read (freed or unmapped memory, an array shorter than its count says, or "
                         "device memory)");
  }
}

}  // namespace

void throw_index_fault(std::size_t domain, std::int64_t cell, int corner, std::int64_t index, std::int64_t vertices,
                       const Vec3& v) {
  // Each message is made only on a fault (the checks run per element)
  const DomainCheck c{domain};
  if (!(index >= 0 && index < vertices))
    c.require(false, cell,
              "vertex index " + std::to_string(index) + " (entry " + std::to_string(corner) + ") is outside [0, " +
                  std::to_string(vertices) + ")");
  c.require(false, cell, "vertex " + std::to_string(index) + " has a non-finite coordinate " + point_text(v));
  throw std::logic_error("throw_index_fault: no fault");
}

void check_mesh_descriptors(const Mesh& mesh) {
  if (mesh.domains.empty()) throw std::invalid_argument("mesh: no domain");
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const MeshDomain& d = mesh.domains[i];
    const DomainCheck c{i};
    check_coords(c, d.coords);
    check_field(c, d, check_topology(c, d));
  }
}

void check_mesh_arrays(const Mesh& mesh) {
  check_mesh_descriptors(mesh);
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) check_memory(DomainCheck{i}, mesh.domains[i]);
}

MeshChecked check_mesh(const Mesh& mesh) {
  check_all_cells(mesh, true);
  return MeshCheckedIssuer::issue(mesh, true);
}

MeshChecked check_mesh_indices(const Mesh& mesh) {
  check_all_cells(mesh, false);
  return MeshCheckedIssuer::issue(mesh, false);
}

MeshChecked check_mesh_copy(const Mesh& mesh) {
  check_all_cells(mesh, false);
  return MeshCheckedIssuer::issue(mesh, true);  // the shapes: the caller's word
}

}  // namespace tessera
