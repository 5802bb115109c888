// geometry_hash (geometry_hash.h): every geometry item through two mixers.
#include "data/geometry_hash.h"

#include <cstring>

namespace tessera::insitu {
namespace {

/// Two streaming 64-bit mixers with different constants and structure.
struct Mixer {
  std::uint64_t a = 0x243f6a8885a308d3ull, b = 0x13198a2e03707344ull;
  void add(std::uint64_t x) {
    a ^= x * 0x9e3779b97f4a7c15ull;
    a = ((a << 31) | (a >> 33)) * 0xbf58476d1ce4e5b9ull;
    b += x ^ 0x94d049bb133111ebull;
    b *= 0xff51afd7ed558ccdull;
    b ^= b >> 29;
  }
  /// `count` items of `size` bytes (1, 4 or 8), `stride` bytes apart from `base`.
  void add_items(const void* base, std::int64_t count, std::int64_t stride, std::size_t size) {
    add(static_cast<std::uint64_t>(count));
    const auto* p = static_cast<const unsigned char*>(base);
    for (std::int64_t i = 0; i < count; ++i, p += stride) {
      std::uint64_t x = 0;
      std::memcpy(&x, p, size);
      add(x);
    }
  }
};

}  // namespace

GeometryHash geometry_hash(const Mesh& mesh) {
  Mixer m;
  m.add(mesh.domains.size());
  for (const MeshDomain& d : mesh.domains) {
    for (const std::int64_t n : d.dims) m.add(static_cast<std::uint64_t>(n));
    m.add(static_cast<std::uint64_t>(d.cell_shape()));
    m.add(static_cast<std::uint64_t>(d.coords.dtype));
    const std::size_t csize = dtype_size(d.coords.dtype);
    for (const void* axis : {d.coords.x, d.coords.y, d.coords.z})
      m.add_items(axis, d.coords.count, d.coords.byte_stride, csize);
    if (!d.structured()) {
      const std::size_t isize = d.index_type == IndexType::Int64 ? 8 : 4;
      m.add(isize);
      const std::int64_t entries = d.ncells * shape_vertex_count(d.shape);
      m.add_items(d.connectivity, entries, static_cast<std::int64_t>(isize), isize);
    }
    m.add(d.ghosts.data ? 1 : 0);
    if (d.ghosts.data) m.add_items(d.ghosts.data, d.ghosts.count, d.ghosts.byte_stride, 1);
  }
  return {m.a, m.b};
}

}  // namespace tessera::insitu
