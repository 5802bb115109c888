/// mesh_geometry_hash (mesh.h) on the host: the item sums over TBB's threads (geometry_hash.h).
#include "mesh/geometry_hash.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>

namespace tessera {

std::vector<GeometryArray> geometry_arrays(const Mesh& mesh) {
  std::vector<GeometryArray> out;
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const MeshDomain& d = mesh.domains[i];
    const auto tag = [&](MeshArraySlot s) { return (static_cast<std::uint64_t>(i) << 8) | static_cast<unsigned>(s); };
    const int csize = static_cast<int>(dtype_size(d.coords.dtype));
    const void* xyz[3] = {d.coords.x, d.coords.y, d.coords.z};
    for (int a = 0; a < 3; ++a)
      out.push_back({static_cast<const unsigned char*>(xyz[a]), d.coords.count, d.coords.byte_stride, csize,
                     tag(static_cast<MeshArraySlot>(a))});
    if (!d.structured()) {
      const int isize = d.index_type == IndexType::Int64 ? 8 : 4;
      out.push_back({static_cast<const unsigned char*>(d.connectivity), d.ncells * shape_vertex_count(d.shape), isize,
                     isize, tag(MeshArraySlot::Connectivity)});
    }
    if (d.ghosts.data)
      out.push_back({d.ghosts.data, d.ghosts.count, d.ghosts.byte_stride, 1, tag(MeshArraySlot::Ghosts)});
  }
  return out;
}

Mesh ghost_masks_only(const Mesh& mesh) {
  Mesh m = mesh;
  for (MeshDomain& d : m.domains) {
    d.coords.count = 0;
    if (!d.structured()) d.ncells = 0;  // (a ghost mask keeps its own count)
  }
  return m;
}

bool has_ghost_masks(const Mesh& mesh) {
  return std::any_of(mesh.domains.begin(), mesh.domains.end(),
                     [](const MeshDomain& d) { return d.ghosts.data != nullptr; });
}

MeshGeometryHash finish_geometry_hash(const Mesh& mesh, const GeometrySums& items) {
  GeometrySums s = items;
  std::uint64_t n = 0;  // the descriptors, as items of a tag no array has
  const auto word = [&](std::int64_t w) { add_geometry_item(s, ~0ull, n++, static_cast<std::uint64_t>(w)); };
  word(static_cast<std::int64_t>(mesh.domains.size()));
  for (const MeshDomain& d : mesh.domains) {
    for (const std::int64_t k : d.dims) word(k);
    word(static_cast<std::int64_t>(d.cell_shape()));
    word(d.structured() ? -1 : static_cast<std::int64_t>(d.index_type));
    word(d.cell_count());
    word(d.coords.count);
    word(static_cast<std::int64_t>(d.coords.dtype));
    word(d.ghosts.data ? d.ghosts.count : -1);
  }
  return MeshGeometryHash{s.a, s.b};
}

GeometrySums geometry_sums(const Mesh& mesh) {
  GeometrySums total;
  for (const GeometryArray& g : geometry_arrays(mesh)) {
    const GeometrySums part = tbb::parallel_reduce(
        tbb::blocked_range<std::int64_t>(0, g.count, 16384), GeometrySums{},
        [&](const auto& r, GeometrySums s) {
          for (std::int64_t i = r.begin(); i != r.end(); ++i)
            add_geometry_item(s, g.tag, static_cast<std::uint64_t>(i), geometry_item(g, i));
          return s;
        },
        [](GeometrySums x, const GeometrySums& y) {
          x.a += y.a;
          x.b += y.b;
          return x;
        });
    total.a += part.a;
    total.b += part.b;
  }
  return total;
}

MeshGeometryHash mesh_geometry_hash(const Mesh& mesh) {
  check_mesh_arrays(mesh);
  return finish_geometry_hash(mesh, geometry_sums(mesh));
}

}  // namespace tessera
