// Curvilinear and unstructured domains bound as core Mesh views (mesh_binding.h).
#include "data/mesh_binding.h"

#include "data/field_binding.h"

#include <algorithm>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

namespace tessera::insitu {
namespace {

[[noreturn]] void fail(std::int64_t d, const std::string& why) {
  throw std::invalid_argument("domain " + std::to_string(d) + ": " + why);
}

std::span<const tessera_field> field_list(const tessera_mesh_domain& m, std::int64_t d) {
  if (m.nfields < 0) fail(d, "nfields = " + std::to_string(m.nfields) + " is negative");
  if (m.nfields > 0 && !m.fields) fail(d, "fields is NULL with nfields = " + std::to_string(m.nfields));
  return {m.fields, static_cast<std::size_t>(m.nfields)};
}

/// The (name, dtype) list of a domain's fields, sorted: what every domain must publish alike.
std::vector<std::pair<std::string, int>> signature(std::span<const tessera_field> fields, std::int64_t d) {
  std::vector<std::pair<std::string, int>> s;
  s.reserve(fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!fields[i].name) fail(d, "fields[" + std::to_string(i) + "]: name is null");
    s.emplace_back(fields[i].name, raw_int(fields[i].dtype));
  }
  std::sort(s.begin(), s.end());
  return s;
}

/// One field array as the core's 1-D view: a 1-D array, or one whose i, j, k elements are
/// consecutive in memory (what a curvilinear domain's 3-D array usually is).
void one_array(const tessera_field& f, const std::string& label, std::int64_t d, const void** data, DType* dtype,
               std::int64_t* stride, std::int64_t* count) {
  for (int a = 0; a < 3; ++a)
    if (f.ghosts_lo[a] != 0 || f.ghosts_hi[a] != 0)
      fail(d, label + ": ghost layers are not used on curvilinear or unstructured meshes (ghosts_lo / ghosts_hi "
                      "must be 0; mark ghost cells with ghost_field)");
  const FieldView v = bind_array(f, "domain " + std::to_string(d) + ": " + label);
  const bool linear =
      v.dims[1] * v.dims[2] == 1 || (v.byte_strides[1] == v.dims[0] * v.byte_strides[0] &&
                                     (v.dims[2] == 1 || v.byte_strides[2] == v.dims[1] * v.byte_strides[1]));
  if (!linear)
    fail(d, label + ": its elements are not consecutive in i, then j, then k (byte_strides " +
                std::to_string(v.byte_strides[0]) + ", " + std::to_string(v.byte_strides[1]) + ", " +
                std::to_string(v.byte_strides[2]) + " for dims " + std::to_string(v.dims[0]) + "x" +
                std::to_string(v.dims[1]) + "x" + std::to_string(v.dims[2]) +
                "): give a 1-D array (dims {n, 1, 1}) or one laid out i fastest");
  if (v.byte_strides[0] <= 0)
    fail(d,
         label + ": byte_strides[0] = " + std::to_string(v.byte_strides[0]) + " (a mesh field's stride must be > 0)");
  *data = v.data;
  *dtype = v.dtype;
  *stride = v.byte_strides[0];
  *count = v.vertex_count();
}

MeshDomain bind_one(const tessera_mesh_domain& m, std::int64_t d, std::span<const tessera_field> fields, int index) {
  MeshDomain out;
  const int assoc = raw_int(m.association);
  if (assoc != TESSERA_VERTEX && assoc != TESSERA_CELL)
    fail(d, "association = " + std::to_string(assoc) + " is neither TESSERA_VERTEX (0) nor TESSERA_CELL (1)");
  const int cdt = raw_int(m.coords.dtype);
  if (cdt != TESSERA_FLOAT32 && cdt != TESSERA_FLOAT64)
    fail(d, "coords.dtype = " + std::to_string(cdt) + " (allowed: TESSERA_FLOAT32, TESSERA_FLOAT64)");
  out.coords = {m.coords.x, m.coords.y, m.coords.z, static_cast<DType>(cdt), m.coords.byte_stride, m.coords.count};
  for (int a = 0; a < 3; ++a) out.dims[a] = m.dims[a];
  if (!out.structured()) {
    const int shape = raw_int(m.shape);
    if (shape < TESSERA_HEX || shape > TESSERA_PYRAMID)
      fail(d, "shape = " + std::to_string(shape) + " is not a tessera_shape (TESSERA_HEX .. TESSERA_PYRAMID)");
    const int idt = raw_int(m.index_dtype);
    if (idt != TESSERA_INT32 && idt != TESSERA_INT64)
      fail(d, "index_dtype = " + std::to_string(idt) + " (allowed: TESSERA_INT32, TESSERA_INT64)");
    out.shape = static_cast<Shape>(shape);
    out.connectivity = m.connectivity;
    out.index_type = idt == TESSERA_INT32 ? IndexType::Int32 : IndexType::Int64;
    out.ncells = m.ncells;
  }
  const tessera_field& f = fields[static_cast<std::size_t>(index)];
  one_array(f, field_label(f), d, &out.field.data, &out.field.dtype, &out.field.byte_stride, &out.field.count);
  out.field.association = assoc == TESSERA_CELL ? Association::Cell : Association::Vertex;
  if (m.ghost_field) {
    const auto it = std::find_if(fields.begin(), fields.end(),
                                 [&](const tessera_field& g) { return std::string(g.name) == m.ghost_field; });
    if (it == fields.end())
      fail(d, "ghost_field '" + std::string(m.ghost_field) + "' is not among the domain's fields");
    if (raw_int(it->dtype) != TESSERA_UINT8)
      fail(d, field_label(*it) + " (the ghost field) is not TESSERA_UINT8 (dtype " +
                  std::to_string(raw_int(it->dtype)) + ")");
    const void* data = nullptr;
    DType dt = DType::UInt8;
    one_array(*it, field_label(*it), d, &data, &dt, &out.ghosts.byte_stride, &out.ghosts.count);
    out.ghosts.data = static_cast<const std::uint8_t*>(data);
  }
  return out;
}

}  // namespace

MeshBinding bind_mesh_domains(const tessera_mesh_domain* domains, std::int64_t n, const std::string& field_name,
                              const std::string& render_name) {
  if (n < 0 || n > TESSERA_MAX_DOMAINS)
    throw std::invalid_argument("ndomains = " + std::to_string(n) + " (allowed: 0 to " +
                                std::to_string(TESSERA_MAX_DOMAINS) + ")");
  if (n > 0 && !domains) throw std::invalid_argument("domains is NULL with ndomains = " + std::to_string(n));
  MeshBinding b;
  b.field = field_name;
  std::vector<std::pair<std::string, int>> first;
  b.local.domains.reserve(static_cast<std::size_t>(n));
  for (std::int64_t d = 0; d < n; ++d) {
    const tessera_mesh_domain& m = domains[d];
    const std::span<const tessera_field> fields = field_list(m, d);
    int index = -1;
    try {
      index = find_field(fields, field_name, render_name);
    } catch (const std::invalid_argument& e) {
      fail(d, e.what());
    }
    if (d == 0) {
      first = signature(fields, d);
      b.field = fields[static_cast<std::size_t>(index)].name;
      b.association = raw_int(m.association) == TESSERA_CELL ? Association::Cell : Association::Vertex;
    } else {
      if (signature(fields, d) != first)
        fail(d, "its fields (names and dtypes) differ from domain 0's: every domain publishes the same fields");
      const Association a = raw_int(m.association) == TESSERA_CELL ? Association::Cell : Association::Vertex;
      if (a != b.association)
        fail(d, std::string("is ") + (a == Association::Cell ? "cell" : "vertex") + " data, domain 0 " +
                    (b.association == Association::Cell ? "cell" : "vertex") + " data");
    }
    MeshDomain md = bind_one(m, d, fields, index);
    b.dtype = md.field.dtype;
    b.vertices += std::max<std::int64_t>(0, md.coords.count);
    b.local.domains.push_back(md);
  }
  return b;
}

}  // namespace tessera::insitu
