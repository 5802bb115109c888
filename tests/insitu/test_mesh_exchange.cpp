// The ranks' exchange of curvilinear and unstructured domains (data/mesh_exchange.h): a packed
// mesh reads back as the same geometry and values; the values packed alone, read over an
// earlier exchange's geometry, give the mesh with the new values and the kept geometry (views
// into both); bytes that do not fit that geometry are refused naming the rank.
#include "data/mesh_binding.h"
#include "data/mesh_exchange.h"
#include "mesh_blocks.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <deque>
#include <string>
#include <vector>

using namespace tessera::insitu;
using Catch::Matchers::Contains;
using tessera_test::MeshBlock;
using Form = tessera_test::MeshBlock::Form;

namespace {

const std::int64_t kN[3] = {5, 4, 6};

/// Element e of a strided array of doubles.
double at(const tessera::MeshField& a, std::int64_t e) {
  double v;
  std::memcpy(&v, static_cast<const unsigned char*>(a.data) + e * a.byte_stride, sizeof v);
  return v;
}

double coord(const void* base, std::int64_t stride, std::int64_t e) {
  double v;
  std::memcpy(&v, static_cast<const unsigned char*>(base) + e * stride, sizeof v);
  return v;
}

/// Two ranks' meshes: rank 0 a curvilinear block and a hex block, rank 1 a tet block.
struct TwoRanks {
  std::deque<MeshBlock> blocks;
  std::vector<tessera_mesh_domain> r0, r1;
  TwoRanks() {
    blocks.emplace_back(kN, 0, 2);
    blocks.emplace_back(kN, 2, 4);
    blocks.emplace_back(kN, 4, 5);
    r0 = {blocks[0].domain(Form::Curvilinear), blocks[1].domain(Form::Hexes)};
    r1 = {blocks[2].domain(Form::Tets)};
  }
  tessera::Mesh mesh(int rank) const {
    const std::vector<tessera_mesh_domain>& d = rank == 0 ? r0 : r1;
    return bind_mesh_domains(d.data(), static_cast<std::int64_t>(d.size()), "f", "view").local;
  }
};

}  // namespace

TEST_CASE("mesh exchange: the values alone over an earlier exchange's geometry", "[insitu][mesh][exchange]") {
  TwoRanks ranks;
  const std::vector<std::string> parts = {pack_mesh(ranks.mesh(0)), pack_mesh(ranks.mesh(1))};
  const tessera::Mesh whole = unpack_meshes(parts);
  REQUIRE(whole.domains.size() == 3);
  // New values on every rank; the geometry is read from `parts`, the values from the new bytes
  for (MeshBlock& b : ranks.blocks)
    for (double& v : b.vertex_values) v = 2.0 * v + 1.0;
  const std::vector<std::string> values = {pack_values(ranks.mesh(0)), pack_values(ranks.mesh(1))};
  const tessera::Mesh updated = unpack_with_values(parts, values);
  REQUIRE(updated.domains.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) {
    const tessera::MeshDomain &a = whole.domains[i], &b = updated.domains[i];
    INFO("domain " << i);
    CHECK(b.coords.x == a.coords.x);  // the kept geometry, not a copy
    CHECK(b.connectivity == a.connectivity);
    REQUIRE(b.field.count == a.field.count);
    for (std::int64_t e = 0; e < b.field.count; ++e) REQUIRE(at(b.field, e) == 2.0 * at(a.field, e) + 1.0);
    for (std::int64_t v = 0; v < b.coords.count; ++v)
      REQUIRE(coord(b.coords.y, b.coords.byte_stride, v) == coord(a.coords.y, a.coords.byte_stride, v));
  }
  tessera::check_mesh(updated);  // a sound mesh

  // Refused, naming the rank: values for another domain count, another count per domain,
  // bytes that end early, a header that is none, more ranks than the geometry has
  CHECK_THROWS_WITH(unpack_with_values(parts, {values[1], values[0]}), Contains("rank 0's values are for 1 domains"));
  std::vector<std::string> bad = values;
  std::int64_t count = 0;
  std::memcpy(&count, &bad[1][16], 8);  // rank 1's domain 0: dtype at 8, count at 16
  --count;
  std::memcpy(&bad[1][16], &count, 8);
  CHECK_THROWS_WITH(unpack_with_values(parts, bad), Contains("rank 1's values count"));
  bad = values;
  bad[1].resize(bad[1].size() - 8);
  CHECK_THROWS_WITH(unpack_with_values(parts, bad), Contains("rank 1's mesh bytes end early"));
  bad = values;
  const std::int64_t nonsense = 99;
  std::memcpy(&bad[0][8], &nonsense, 8);  // domain 0's dtype
  CHECK_THROWS_WITH(unpack_with_values(parts, bad), Contains("rank 0's values hold an invalid header"));
  CHECK_THROWS_WITH(unpack_with_values(parts, {values[0]}), Contains("the values of 1 ranks for a mesh of 2"));
}
