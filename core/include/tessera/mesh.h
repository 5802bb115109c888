#pragma once
/// Curvilinear and unstructured meshes (Blueprint's `explicit` coordsets with `structured` and
/// `unstructured` topologies; interfaces.md 7.2, physics.md section 10) as non-owning,
/// zero-copy views of the caller's arrays. Nothing here is copied or converted: every array
/// must stay valid and unchanged while a prepared scene made from it lives.
///
/// A Mesh is one or more domains; each domain is a curvilinear grid (dims > 0: a logical
/// i, j, k grid of explicit vertices, i fastest) or a list of elements of one shape
/// (connectivity in Blueprint's / VTK's vertex order), with one scalar field per vertex or
/// per cell and an optional ghost mask per cell (nonzero: a ghost, never sampled). The image
/// does not depend on how the cells are cut into domains nor on their order.
#include <tessera/field_view.h>
#include <tessera/host_device.h>
#include <tessera/scene.h>

#include <cstdint>
#include <string>
#include <vector>

namespace tessera {

/// The integer type of a connectivity array.
enum class IndexType : int { Int32 = 0, Int64 = 1 };

/// An unstructured element shape (VTK's vertex order, as Blueprint's): hex 8 vertices (0-3
/// the bottom face counter-clockwise seen from 4-7 above it), tet 4 (0-2 counter-clockwise
/// seen from 3), wedge 6, pyramid 5. Wedge and pyramid are refused for now.
enum class Shape : int { Hex = 0, Tet = 1, Wedge = 2, Pyramid = 3 };

/// Vertices of one element of `shape`.
int shape_vertex_count(Shape shape);
const char* shape_name(Shape shape);

/// Explicit vertex coordinates: vertex v's x at (const char*)x + v * byte_stride (likewise
/// y, z), in dtype Float32 or Float64.
struct MeshCoords {
  const void* x = nullptr;
  const void* y = nullptr;
  const void* z = nullptr;
  DType dtype = DType::Float64;
  std::int64_t byte_stride = 0;  ///< >= the dtype's size; the same for x, y and z
  std::int64_t count = 0;        ///< vertices
};

/// One scalar array: element e at (const char*)data + e * byte_stride.
struct MeshField {
  const void* data = nullptr;
  DType dtype = DType::Float32;
  std::int64_t byte_stride = 0;  ///< >= the dtype's size
  std::int64_t count = 0;        ///< values: coords.count (vertex data) or the cell count (cell data)
  Association association = Association::Vertex;
};

/// An optional ghost mask: one uint8 per cell, nonzero = a ghost (never sampled).
struct MeshGhosts {
  const std::uint8_t* data = nullptr;  ///< null: no ghosts
  std::int64_t byte_stride = 1;
  std::int64_t count = 0;  ///< the cell count when data is set

  /// Whether cell `cell` (< count) is a ghost; always false without a mask. Reads the mask
  /// where it is (host or device code, memory of the caller's side).
  TESSERA_HOST_DEVICE bool is_ghost(std::int64_t cell) const {
    return data != nullptr && data[cell * byte_stride] != 0;
  }
};

/// The arrays a domain's render reads, by slot.
enum class MeshArraySlot : int { X = 0, Y, Z, Connectivity, Field, Ghosts };
inline constexpr int kMeshArraySlots = 6;

/// One curvilinear or unstructured domain.
struct MeshDomain {
  MeshCoords coords;
  /// Curvilinear: vertices per logical axis (each >= 2; coords.count = dims[0] dims[1]
  /// dims[2]); cell (i, j, k) is the hex of vertices (i..i+1, j..j+1, k..k+1).
  /// Unstructured: all 0.
  std::int64_t dims[3] = {0, 0, 0};
  Shape shape = Shape::Hex;            ///< unstructured: the element shape
  const void* connectivity = nullptr;  ///< unstructured: ncells x shape_vertex_count indices
  IndexType index_type = IndexType::Int32;
  std::int64_t ncells = 0;  ///< unstructured: elements; curvilinear: ignored
  MeshField field;
  MeshGhosts ghosts;
  /// Optional, per slot (MeshArraySlot): the same bytes as that array in GPU device memory
  /// (the original of a host copy the caller made to have the mesh checked and its tables
  /// built on the host). A render on the GPU reads them there instead of copying the host
  /// array; the CPU never reads them. Null: none (the GPU render copies the host array).
  const void* device_copy[kMeshArraySlots] = {};

  bool structured() const { return dims[0] != 0 || dims[1] != 0 || dims[2] != 0; }
  /// Cells: ncells, or (dims[0]-1)(dims[1]-1)(dims[2]-1) for a curvilinear grid (after check_mesh).
  std::int64_t cell_count() const;
  /// The shape of every cell: Hex for a curvilinear grid.
  Shape cell_shape() const { return structured() ? Shape::Hex : shape; }
};

/// The whole mesh: its domains (views; the vector is the caller's small list of them).
struct Mesh {
  std::vector<MeshDomain> domains;
  /// Every array is GPU memory (a CUDA device's), read where it is: prepare() then needs
  /// `reuse` to fit (the layout is built on the host, by an earlier prepare of the same
  /// geometry), checks the indices and summarises the values on the device, and the scene
  /// renders on the GPU only (options.device = Cuda). The host never reads the arrays.
  bool device = false;
};

/// The values of a mesh as a check on the device measured them (cuda_check_mesh_indices): the
/// count, the NaN count and the min / max of the finite ones (zeros as +0.0; every value,
/// ghosts' too), and the finite min / max with ghost cells' values left out for cell data
/// (+Inf, -Inf when none is finite).
struct MeshValueTotals {
  std::uint64_t values = 0, nan = 0;
  double lo = 0.0, hi = 0.0;
  double real_lo = 0.0, real_hi = 0.0;
};

/// A receipt: what a check of one mesh's arrays established (check_mesh: indices and shapes;
/// check_mesh_indices or cuda_check_mesh_indices: indices), so that prepare() can take it
/// instead of checking the same arrays again in the same step. It covers a mesh whose domains
/// have exactly the descriptors of the one checked (the same pointers, counts, strides,
/// dtypes, dims, shapes and masks) and the same Mesh::device; only the check functions make a
/// non-empty one. Passing it is the caller's promise that the arrays' contents have not
/// changed since the check (as a simulation's do not while it waits for the render); a
/// mesh it does not cover is checked as if none were given. Holds one copy of the domains'
/// descriptors (no array).
class MeshChecked {
 public:
  MeshChecked() = default;  ///< covers nothing
  /// Whether this receipt covers `mesh`, with its shapes (`shapes`: a check_mesh's) or not.
  bool covers(const Mesh& mesh, bool shapes) const;
  /// The values' totals, when the check measured them (cuda_check_mesh_indices); else null.
  const MeshValueTotals* values() const { return m_has_values ? &m_values : nullptr; }
  /// This receipt carried over to `mesh`, whose domains differ from those it covers in their
  /// fields' data pointers only (the same geometry arrays, ghost masks and device copies, the
  /// fields' dtypes, strides, counts and associations): what the check read is unchanged, and
  /// each new field is as long as the old one. Covers nothing otherwise. The values' totals
  /// are not carried (they were the old values'). The caller vouches that each new field's
  /// `count` elements at its stride are readable memory (the check probed the old ones).
  MeshChecked with_new_values(const Mesh& mesh) const;

 private:
  friend struct MeshCheckedIssuer;  // core/src/mesh/mesh_checked_issuer.h: the check functions'
  std::vector<MeshDomain> m_domains;
  bool m_device = false;
  bool m_shapes = false;
  bool m_has_values = false;
  MeshValueTotals m_values;
};

/// Checks every domain, in time and memory linear in the mesh (one pass over the elements and
/// the values, no allocation proportional to it; the elements over the threads of the
/// caller's TBB arena), and throws std::invalid_argument whose message begins "mesh domain D"
/// (and names "element E", the lowest at fault in the first faulty domain, whatever the
/// thread count) for:
/// no domain or no cell; negative counts or strides below the dtype size; counts x strides
/// overflowing int64; a non-float coordinate dtype or unknown index type or shape (wedge and
/// pyramid: not supported yet); null arrays; dims that do not match the vertex count; an index
/// out of range; NaN or Inf coordinates of an element's vertex; a degenerate or inverted
/// element (a corner Jacobian of a hex, or a tet's volume, not above 1e-12 of its edge length
/// cubed, or of the wrong sign: unstructured elements must be positively oriented in VTK's
/// order, a curvilinear grid's cells must all share the first one's orientation); a hex whose
/// trilinear map Newton's method cannot invert at interior test points to 1e-10 of its size;
/// a field or ghost mask whose length is not the vertex or cell count; an array whose memory
/// cannot be read (check_mesh_arrays below). Returns its receipt (MeshChecked) for prepare().
MeshChecked check_mesh(const Mesh& mesh);

/// What check_mesh checks of each domain's descriptors (counts, strides, dtypes, shapes,
/// null arrays, the field's and ghost mask's lengths) and that each array's memory can be read
/// (unreadable_byte, host_readable.h: 64 bytes probed per array, so freed or unmapped memory
/// or an array shorter than its count is an error naming it, not a fault), in time linear in
/// the domains, reading no coordinate, index or value otherwise.
void check_mesh_arrays(const Mesh& mesh);

/// check_mesh without the shapes: check_mesh_arrays, then every real cell's vertex indices in
/// range and its vertices' coordinates finite (one pass over the elements, no Jacobian, no
/// Newton), and at least one real cell; throws as check_mesh does for those faults. What a
/// mesh needs whose elements an earlier check_mesh accepted and that the caller promises
/// unchanged (prepare's `reuse`, render.h): a broken promise then gives wrong lookups, never a
/// read outside the arrays. Returns its receipt (MeshChecked: indices, not shapes).
MeshChecked check_mesh_indices(const Mesh& mesh);

/// check_mesh_indices of a mesh made of copies of meshes that check_mesh accepted (the other
/// ranks' domains, received after each rank checked its own), whose receipt also stands for
/// the shapes: the caller's word that every element's shape is one check_mesh accepted, so
/// that prepare() builds a new layout without checking the shapes again. The indices and
/// vertices are checked (a false word gives a wrong image, never a read outside the arrays).
MeshChecked check_mesh_copy(const Mesh& mesh);

/// What check_mesh_arrays checks of the descriptors alone (counts, strides, dtypes, shapes,
/// null arrays, the field's and ghost mask's lengths), reading no array's memory: for arrays
/// that are not host memory yet (a GPU's, before they are copied to the host). Throws as
/// check_mesh does.
void check_mesh_descriptors(const Mesh& mesh);

/// Two independent 64-bit hashes of what a mesh's layout depends on: its domains' counts,
/// dims, shapes and dtypes, every vertex's coordinates, every connectivity entry and every
/// ghost flag, never the values (so that a caller can tell a geometry that is the same bit
/// for bit as an earlier one, and reuse its layout: prepare's `reuse`). The same geometry in
/// other arrays (other pointers or strides) has the same hash. An accidental match of another
/// geometry needs both to collide (about 2^-128); not cryptographic. check_mesh_arrays first
/// (throws as it does), then one pass over the items over the caller's arena's threads: the
/// same value under any thread count. cuda_mesh_geometry_hash (cuda_render.h) gives the same
/// value for arrays in GPU memory.
struct MeshGeometryHash {
  std::uint64_t a = 0, b = 0;
  bool operator==(const MeshGeometryHash&) const = default;
};
MeshGeometryHash mesh_geometry_hash(const Mesh& mesh);

/// One array of a domain: its pointer (null where the domain has none: a curvilinear
/// domain's connectivity, no ghost mask, a zero count), the bytes it spans from there, and
/// its name as messages give it ("coords.x", "the connectivity", "the field", ...).
struct MeshArraySpan {
  const void* data = nullptr;
  std::int64_t bytes = 0;
  const char* name = "";
};

/// Slot `s` of `d`, whose descriptors check_mesh_descriptors accepted (so the span fits int64).
MeshArraySpan mesh_array(const MeshDomain& d, MeshArraySlot s);
/// Points slot `s` of `d` at `data`: the same bytes elsewhere (a host copy of a GPU array).
void set_mesh_array(MeshDomain& d, MeshArraySlot s, const void* data);

}  // namespace tessera
