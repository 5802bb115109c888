#pragma once
/// Helpers of the mesh tests (test_mesh_*.cpp): meshes built as plain vertex and element lists
/// (VTK order), cut into domains (each domain with its own compacted vertex arrays, in any
/// order, int32 or int64 indices), curvilinear grids, and a block z-test of two films.
#include <tessera/film.h>
#include <tessera/mesh.h>

#include "../common/block_z_test.h"
#include "mesh/element_geometry.h"
#include "sampling/rng.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace tessera_mesh_test {

using tessera::Vec3;

/// A mesh as one list of vertices (position, value) and elements (vertex ids, VTK order).
struct ElementList {
  tessera::Shape shape = tessera::Shape::Hex;
  std::vector<Vec3> vertex;
  std::vector<double> value;  ///< per vertex (vertex data) or per element (cell data)
  tessera::Association association = tessera::Association::Vertex;
  std::vector<std::vector<std::int64_t>> element;
};

/// The arrays behind one domain (owned here, viewed by the MeshDomain).
struct OwnedDomain {
  std::vector<double> x, y, z, values;
  std::vector<std::int32_t> conn32;
  std::vector<std::int64_t> conn64;
  std::vector<std::uint8_t> ghosts;
  tessera::MeshDomain domain;
};

/// A mesh and the arrays it views.
struct OwnedMesh {
  std::vector<std::unique_ptr<OwnedDomain>> owned;
  tessera::Mesh mesh;
};

/// Vertices of an nx x ny x nz-cell grid of `h` spacing from `origin`, moved by `warp`, with
/// values f(position) (vertex data), and its hexes (VTK order, cells x fastest).
inline ElementList grid_hexes(int nx, int ny, int nz, const Vec3& origin, const Vec3& h,
                              const std::function<double(const Vec3&)>& f,
                              const std::function<Vec3(const Vec3&)>& warp = nullptr) {
  ElementList m;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        Vec3 p = origin + Vec3(i, j, k) * h;
        if (warp) p = warp(p);
        m.vertex.push_back(p);
        m.value.push_back(f(p));
      }
  const auto id = [&](int i, int j, int k) { return static_cast<std::int64_t>((k * (ny + 1) + j) * (nx + 1) + i); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.element.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                             id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  return m;
}

/// Each hex cut into 6 tets around its diagonal 0-6 (conforming between neighbours of a grid),
/// each positively oriented.
inline ElementList hexes_to_tets(const ElementList& hexes) {
  ElementList t = hexes;
  t.shape = tessera::Shape::Tet;
  t.element.clear();
  static constexpr int kTets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                      {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  for (const auto& h : hexes.element)
    for (const auto& q : kTets) {
      std::vector<std::int64_t> e = {h[q[0]], h[q[1]], h[q[2]], h[q[3]]};
      const Vec3 c[4] = {hexes.vertex[e[0]], hexes.vertex[e[1]], hexes.vertex[e[2]], hexes.vertex[e[3]]};
      if (tessera::tet_volume6(c) < 0.0) std::swap(e[1], e[2]);
      t.element.push_back(e);
    }
  return t;
}

/// The elements cut into domains: element e goes to domain part[e]; the domains are listed in
/// `order`, each with its own vertices (renumbered in the order of their first use) and its
/// elements in reverse when `reverse`. int64 indices where `wide`.
inline OwnedMesh cut(const ElementList& m, const std::vector<int>& part, const std::vector<int>& order,
                     bool reverse = false, bool wide = false) {
  OwnedMesh out;
  for (const int d : order) {
    auto od = std::make_unique<OwnedDomain>();
    std::vector<std::int64_t> local(m.vertex.size(), -1);
    std::vector<std::size_t> mine;
    for (std::size_t e = 0; e < m.element.size(); ++e)
      if (part[e] == d) mine.push_back(e);
    if (reverse) std::reverse(mine.begin(), mine.end());
    std::int64_t nv = 0;
    for (const std::size_t e : mine)
      for (const std::int64_t v : m.element[e]) {
        if (local[static_cast<std::size_t>(v)] < 0) {
          local[static_cast<std::size_t>(v)] = nv++;
          const Vec3& p = m.vertex[static_cast<std::size_t>(v)];
          od->x.push_back(p.x);
          od->y.push_back(p.y);
          od->z.push_back(p.z);
          if (m.association == tessera::Association::Vertex) od->values.push_back(m.value[static_cast<std::size_t>(v)]);
        }
        od->conn64.push_back(local[static_cast<std::size_t>(v)]);
        od->conn32.push_back(static_cast<std::int32_t>(local[static_cast<std::size_t>(v)]));
      }
    if (m.association == tessera::Association::Cell)
      for (const std::size_t e : mine) od->values.push_back(m.value[e]);
    tessera::MeshDomain& md = od->domain;
    md.coords = {od->x.data(), od->y.data(), od->z.data(), tessera::DType::Float64, 8, nv};
    md.shape = m.shape;
    md.index_type = wide ? tessera::IndexType::Int64 : tessera::IndexType::Int32;
    md.connectivity = wide ? static_cast<const void*>(od->conn64.data()) : static_cast<const void*>(od->conn32.data());
    md.ncells = static_cast<std::int64_t>(mine.size());
    md.field = {od->values.data(), tessera::DType::Float64, 8, static_cast<std::int64_t>(od->values.size()),
                m.association};
    out.mesh.domains.push_back(md);
    out.owned.push_back(std::move(od));
  }
  return out;
}

/// The whole list as one domain.
inline OwnedMesh one_domain(const ElementList& m) { return cut(m, std::vector<int>(m.element.size(), 0), {0}); }

/// A curvilinear domain over the vertices of grid_hexes(nx, ny, nz, ...) (same vertex order).
inline OwnedMesh curvilinear(const ElementList& m, int nx, int ny, int nz) {
  OwnedMesh out;
  auto od = std::make_unique<OwnedDomain>();
  for (const Vec3& p : m.vertex) {
    od->x.push_back(p.x);
    od->y.push_back(p.y);
    od->z.push_back(p.z);
  }
  od->values = m.value;
  tessera::MeshDomain& md = od->domain;
  md.coords = {
      od->x.data(), od->y.data(), od->z.data(), tessera::DType::Float64, 8, static_cast<std::int64_t>(m.vertex.size())};
  md.dims[0] = nx + 1;
  md.dims[1] = ny + 1;
  md.dims[2] = nz + 1;
  md.field = {od->values.data(), tessera::DType::Float64, 8, static_cast<std::int64_t>(od->values.size()),
              m.association};
  out.mesh.domains.push_back(md);
  out.owned.push_back(std::move(od));
  return out;
}

using tessera_test::block_stats;
using tessera_test::BlockStat;
using tessera_test::max_block_z;

}  // namespace tessera_mesh_test
