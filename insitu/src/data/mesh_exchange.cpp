// Packing curvilinear and unstructured domains for the ranks' exchange (mesh_exchange.h).
#include "data/mesh_exchange.h"

#include <cstring>
#include <stdexcept>

namespace tessera::insitu {
namespace {

constexpr int kHeader = 14;  ///< int64 words per domain header

std::uint64_t padded(std::uint64_t bytes) { return (bytes + 7) / 8 * 8; }

/// Bytes of each part of a domain: coords (one axis), connectivity, values, ghosts.
struct Sizes {
  std::uint64_t axis = 0, conn = 0, values = 0, ghosts = 0;
  std::uint64_t total() const {
    return 8 * kHeader + 3 * padded(axis) + padded(conn) + padded(values) + padded(ghosts);
  }
};

Sizes sizes_of(const MeshDomain& d) {
  Sizes s;
  s.axis = static_cast<std::uint64_t>(d.coords.count) * dtype_size(d.coords.dtype);
  if (!d.structured())
    s.conn = static_cast<std::uint64_t>(d.ncells) * static_cast<std::uint64_t>(shape_vertex_count(d.shape)) *
             (d.index_type == IndexType::Int32 ? 4u : 8u);
  s.values = static_cast<std::uint64_t>(d.field.count) * dtype_size(d.field.dtype);
  s.ghosts = d.ghosts.data ? static_cast<std::uint64_t>(d.ghosts.count) : 0;
  return s;
}

/// n elements of `size` bytes, `stride` apart from `src`, appended densely (and padded).
void put(std::string& out, const void* src, std::int64_t n, std::size_t size, std::int64_t stride) {
  const std::size_t at = out.size();
  out.resize(at + padded(static_cast<std::uint64_t>(n) * size), '\0');
  const auto* p = static_cast<const unsigned char*>(src);
  for (std::int64_t e = 0; e < n; ++e) std::memcpy(&out[at + static_cast<std::size_t>(e) * size], p + e * stride, size);
}

/// Reads packed bytes, refusing to read past their end.
struct Reader {
  const std::string& bytes;
  std::size_t at = 0;
  int rank;
  const unsigned char* take(std::uint64_t n) {
    if (n > bytes.size() - at) throw std::invalid_argument("rank " + std::to_string(rank) + "'s mesh bytes end early");
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data()) + at;
    at += static_cast<std::size_t>(padded(n));
    if (at > bytes.size()) at = bytes.size();
    return p;
  }
  std::int64_t word() {
    std::int64_t w;
    std::memcpy(&w, take(8), 8);
    return w;
  }
};

}  // namespace

std::uint64_t packed_mesh_bytes(const Mesh& mesh) {
  std::uint64_t n = 8;
  for (const MeshDomain& d : mesh.domains) n += sizes_of(d).total();
  return n;
}

std::string pack_mesh(const Mesh& mesh) {
  std::string out;
  out.reserve(static_cast<std::size_t>(packed_mesh_bytes(mesh)));
  const std::int64_t count = static_cast<std::int64_t>(mesh.domains.size());
  put(out, &count, 1, 8, 8);
  for (const MeshDomain& d : mesh.domains) {
    const std::int64_t h[kHeader] = {d.dims[0],
                                     d.dims[1],
                                     d.dims[2],
                                     static_cast<std::int64_t>(d.shape),
                                     static_cast<std::int64_t>(d.index_type),
                                     d.structured() ? 0 : d.ncells,
                                     static_cast<std::int64_t>(d.coords.dtype),
                                     d.coords.count,
                                     static_cast<std::int64_t>(d.field.dtype),
                                     d.field.count,
                                     static_cast<std::int64_t>(d.field.association),
                                     d.ghosts.data ? d.ghosts.count : -1,
                                     0,
                                     0};
    put(out, h, kHeader, 8, 8);
    const std::size_t cs = dtype_size(d.coords.dtype);
    for (const void* axis : {d.coords.x, d.coords.y, d.coords.z})
      put(out, axis, d.coords.count, cs, d.coords.byte_stride);
    if (!d.structured()) {
      const std::size_t is = d.index_type == IndexType::Int32 ? 4 : 8;
      const std::int64_t n = d.ncells * shape_vertex_count(d.shape);
      put(out, d.connectivity, n, is, static_cast<std::int64_t>(is));
    }
    put(out, d.field.data, d.field.count, dtype_size(d.field.dtype), d.field.byte_stride);
    if (d.ghosts.data) put(out, d.ghosts.data, d.ghosts.count, 1, d.ghosts.byte_stride);
  }
  return out;
}

namespace {

/// Rank r's packed domains appended to `mesh`, as views into `part`.
void append_domains(const std::string& part, std::size_t r, Mesh& mesh) {
  Reader in{part, 0, static_cast<int>(r)};
  if (part.empty()) return;  // a rank that passed no domain packs nothing at all
  const std::int64_t count = in.word();
  if (count < 0 || static_cast<std::uint64_t>(count) > part.size() / (8 * kHeader))
    throw std::invalid_argument("rank " + std::to_string(r) + "'s mesh bytes hold no valid domain count");
  for (std::int64_t n = 0; n < count; ++n) {
    std::int64_t h[kHeader];
    for (std::int64_t& w : h) w = in.word();
    MeshDomain d;
    for (int a = 0; a < 3; ++a) d.dims[a] = h[a];
    d.shape = static_cast<Shape>(h[3]);
    d.index_type = static_cast<IndexType>(h[4]);
    d.ncells = h[5];
    d.coords.dtype = static_cast<DType>(h[6]);
    d.coords.count = h[7];
    d.field.dtype = static_cast<DType>(h[8]);
    d.field.count = h[9];
    d.field.association = static_cast<Association>(h[10]);
    if (d.coords.count < 0 || d.field.count < 0 || d.ncells < 0 || h[6] < 0 || h[6] > 4 || h[8] < 0 || h[8] > 4 ||
        h[3] < 0 || h[3] > 3 || h[4] < 0 || h[4] > 1)
      throw std::invalid_argument("rank " + std::to_string(r) + "'s mesh bytes hold an invalid domain header");
    const auto size = static_cast<std::int64_t>(part.size());
    if (d.coords.count > size || d.field.count > size || d.ncells > size || h[11] > size)
      throw std::invalid_argument("rank " + std::to_string(r) + "'s mesh bytes hold counts larger than themselves");
    const Sizes s = sizes_of(d);
    const std::size_t cs = dtype_size(d.coords.dtype);
    d.coords.byte_stride = static_cast<std::int64_t>(cs);
    d.coords.x = in.take(s.axis);
    d.coords.y = in.take(s.axis);
    d.coords.z = in.take(s.axis);
    if (!d.structured()) d.connectivity = in.take(s.conn);
    d.field.byte_stride = static_cast<std::int64_t>(dtype_size(d.field.dtype));
    d.field.data = in.take(s.values);
    if (h[11] >= 0) {
      d.ghosts.count = h[11];
      d.ghosts.byte_stride = 1;
      d.ghosts.data = in.take(static_cast<std::uint64_t>(h[11]));
    }
    mesh.domains.push_back(d);
  }
}

}  // namespace

Mesh unpack_meshes(const std::vector<std::string>& parts) {
  Mesh mesh;
  for (std::size_t r = 0; r < parts.size(); ++r) append_domains(parts[r], r, mesh);
  return mesh;
}

std::string pack_values(const Mesh& mesh) {
  std::uint64_t bytes = 8;
  for (const MeshDomain& d : mesh.domains) bytes += 8 * 3 + padded(sizes_of(d).values);
  std::string out;
  out.reserve(static_cast<std::size_t>(bytes));
  const std::int64_t count = static_cast<std::int64_t>(mesh.domains.size());
  put(out, &count, 1, 8, 8);
  for (const MeshDomain& d : mesh.domains) {
    const std::int64_t h[3] = {static_cast<std::int64_t>(d.field.dtype), d.field.count,
                               static_cast<std::int64_t>(d.field.association)};
    put(out, h, 3, 8, 8);
    put(out, d.field.data, d.field.count, dtype_size(d.field.dtype), d.field.byte_stride);
  }
  return out;
}

Mesh unpack_with_values(const std::vector<std::string>& parts, const std::vector<std::string>& values) {
  if (parts.size() != values.size())
    throw std::invalid_argument("the values of " + std::to_string(values.size()) + " ranks for a mesh of " +
                                std::to_string(parts.size()));
  Mesh mesh;
  for (std::size_t r = 0; r < parts.size(); ++r) {
    Mesh own;
    append_domains(parts[r], r, own);
    const std::string rank = "rank " + std::to_string(r);
    Reader in{values[r], 0, static_cast<int>(r)};
    const std::int64_t count = values[r].empty() ? 0 : in.word();
    if (count != static_cast<std::int64_t>(own.domains.size()))
      throw std::invalid_argument(rank + "'s values are for " + std::to_string(count) + " domains, its mesh has " +
                                  std::to_string(own.domains.size()));
    for (MeshDomain d : own.domains) {
      const std::int64_t dtype = in.word(), n = in.word(), association = in.word();
      if (dtype < 0 || dtype > 4 ||
          (association != static_cast<std::int64_t>(Association::Vertex) &&
           association != static_cast<std::int64_t>(Association::Cell)))
        throw std::invalid_argument(rank + "'s values hold an invalid header");
      d.field.association = static_cast<Association>(association);
      const std::int64_t want = d.field.association == Association::Cell ? d.cell_count() : d.coords.count;
      if (n != want)
        throw std::invalid_argument(rank + "'s values count " + std::to_string(n) + " for a domain of " +
                                    std::to_string(want) +
                                    (d.field.association == Association::Cell ? " cells" : " vertices"));
      d.field.dtype = static_cast<DType>(dtype);
      d.field.count = n;
      d.field.byte_stride = static_cast<std::int64_t>(dtype_size(d.field.dtype));
      d.field.data = in.take(static_cast<std::uint64_t>(n) * dtype_size(d.field.dtype));
      mesh.domains.push_back(d);
    }
  }
  return mesh;
}

}  // namespace tessera::insitu
