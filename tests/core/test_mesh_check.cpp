// check_mesh (mesh.h) and prepare(const Mesh&): every class of bad input is refused with a
// std::invalid_argument whose message names the domain (and the element where one is at
// fault), before anything is built; a sound mesh passes.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include <tbb/task_arena.h>

#include <sys/mman.h>
#include <unistd.h>

#include "test_mesh_support.h"

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

using tessera::Vec3;
using namespace tessera_mesh_test;

namespace {

double one(const Vec3&) { return 1.0; }

/// The message check_mesh throws for `mesh` ("" when it accepts it).
std::string fault(const tessera::Mesh& mesh) {
  try {
    tessera::check_mesh(mesh);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

/// Two domains of a 2x2x2 hex grid (domain 1 holds the last 4 cells); `edit` spoils domain 1.
std::string fault_in_second(const std::function<void(OwnedDomain&, tessera::MeshDomain&)>& edit,
                            tessera::Shape shape = tessera::Shape::Hex) {
  ElementList m = grid_hexes(2, 2, 2, Vec3(0.0), Vec3(1.0), one);
  if (shape == tessera::Shape::Tet) m = hexes_to_tets(m);
  std::vector<int> part(m.element.size(), 0);
  for (std::size_t e = m.element.size() / 2; e < m.element.size(); ++e) part[e] = 1;
  OwnedMesh om = cut(m, part, {0, 1});
  edit(*om.owned[1], om.mesh.domains[1]);
  return fault(om.mesh);
}

}  // namespace

TEST_CASE("mesh: check_mesh accepts sound meshes", "[mesh]") {
  const ElementList m = grid_hexes(2, 3, 2, Vec3(0.0), Vec3(0.5), one);
  CHECK(fault(one_domain(m).mesh).empty());
  CHECK(fault(one_domain(hexes_to_tets(m)).mesh).empty());
  CHECK(fault(curvilinear(m, 2, 3, 2).mesh).empty());
  CHECK(fault_in_second([](OwnedDomain&, tessera::MeshDomain&) {}).empty());
}

TEST_CASE("mesh: every bad input names its domain and element", "[mesh]") {
  using D = tessera::MeshDomain;
  using O = OwnedDomain;
  SECTION("an index out of range") {
    const std::string f = fault_in_second([](O& o, D&) { o.conn32[8 + 3] = 1000; });
    INFO(f);
    CHECK(starts_with(f, "mesh domain 1: element 1: vertex index 1000 (entry 3) is outside [0, "));
  }
  SECTION("a negative index (int64)") {
    ElementList m = grid_hexes(2, 1, 1, Vec3(0.0), Vec3(1.0), one);
    OwnedMesh om = cut(m, {0, 0}, {0}, false, true);
    om.owned[0]->conn64[9] = -1;
    CHECK(starts_with(fault(om.mesh), "mesh domain 0: element 1: vertex index -1"));
  }
  SECTION("negative counts") {
    CHECK(starts_with(fault_in_second([](O&, D& d) { d.ncells = -2; }), "mesh domain 1: element count -2 is negative"));
    CHECK(starts_with(fault_in_second([](O&, D& d) { d.coords.count = -1; }),
                      "mesh domain 1: vertex count -1 is negative"));
  }
  SECTION("counts x strides that overflow int64") {
    const std::int64_t big = std::numeric_limits<std::int64_t>::max() / 4;
    CHECK(starts_with(fault_in_second([&](O&, D& d) { d.coords.count = big; }), "mesh domain 1: "));
    CHECK(fault_in_second([&](O&, D& d) { d.coords.count = big; }).find("overflow int64") != std::string::npos);
    CHECK(fault_in_second([&](O&, D& d) { d.ncells = big; }).find("overflow int64") != std::string::npos);
    CHECK(fault_in_second([&](O&, D& d) { d.field.byte_stride = big; }).find("overflow int64") != std::string::npos);
  }
  SECTION("NaN and Inf coordinates") {
    const std::string nan = fault_in_second([](O& o, D&) { o.x[5] = std::nan(""); });
    INFO(nan);
    CHECK(starts_with(nan, "mesh domain 1: element "));
    CHECK(nan.find("non-finite coordinate") != std::string::npos);
    const std::string inf = fault_in_second([](O& o, D&) { o.z[0] = INFINITY; });
    CHECK(starts_with(inf, "mesh domain 1: element 0: vertex 0 has a non-finite coordinate"));
  }
  SECTION("degenerate and inverted hexes") {
    // four separate unit cubes, domain 1 the last three; its element 2: the top face pushed
    // onto the bottom face (flat) or through it (inverted)
    ElementList m;
    for (int c = 0; c < 4; ++c) {
      const ElementList one_cube = grid_hexes(1, 1, 1, Vec3(2.0 * c, 0.0, 0.0), Vec3(1.0), one);
      std::vector<std::int64_t> e;
      for (const std::int64_t v : one_cube.element[0]) e.push_back(v + static_cast<std::int64_t>(m.vertex.size()));
      m.vertex.insert(m.vertex.end(), one_cube.vertex.begin(), one_cube.vertex.end());
      m.value.insert(m.value.end(), one_cube.value.begin(), one_cube.value.end());
      m.element.push_back(e);
    }
    const auto move_top = [&](double dz) {
      OwnedMesh om = cut(m, {0, 1, 1, 1}, {0, 1});
      const std::int32_t* c = om.owned[1]->conn32.data() + 2 * 8;
      for (int k = 4; k < 8; ++k) om.owned[1]->z[static_cast<std::size_t>(c[k])] += dz;
      return fault(om.mesh);
    };
    const std::string flat = move_top(-1.0), inverted = move_top(-1.5);
    INFO(flat << "\n" << inverted);
    CHECK(starts_with(flat, "mesh domain 1: element 2: hex is degenerate"));
    CHECK(starts_with(inverted, "mesh domain 1: element 2: hex is inverted"));
  }
  SECTION("degenerate and inverted tets") {
    const std::string inverted =
        fault_in_second([](O& o, D&) { std::swap(o.conn32[4 * 3 + 1], o.conn32[4 * 3 + 2]); }, tessera::Shape::Tet);
    CHECK(starts_with(inverted, "mesh domain 1: element 3: tet is inverted"));
    const std::string flat =
        fault_in_second([](O& o, D&) { o.conn32[4 * 3 + 3] = o.conn32[4 * 3 + 2]; }, tessera::Shape::Tet);
    CHECK(starts_with(flat, "mesh domain 1: element 3: tet is degenerate"));
  }
  SECTION("a curvilinear cell folded against its grid") {
    ElementList m = grid_hexes(3, 2, 2, Vec3(0.0), Vec3(1.0), one);
    m.vertex[static_cast<std::size_t>(m.element[7][6])].x -= 1.8;  // cell 7's vertex 6 pulled through it
    const std::string f = fault(curvilinear(m, 3, 2, 2).mesh);
    INFO(f);
    CHECK(starts_with(f, "mesh domain 0: element 7: hex is "));
  }
  SECTION("a field of the wrong length") {
    const std::string f = fault_in_second([](O&, D& d) { d.field.count -= 1; });
    CHECK(starts_with(f, "mesh domain 1: the field has "));
    CHECK(f.find("vertex data needs") != std::string::npos);
    const std::string c = fault_in_second([](O&, D& d) { d.field.association = tessera::Association::Cell; });
    CHECK(c.find("cell data needs 4 (one per cell)") != std::string::npos);
  }
  SECTION("a ghost mask of the wrong length") {
    std::vector<std::uint8_t> g(3, 0);
    const std::string f = fault_in_second([&](O&, D& d) { d.ghosts = {g.data(), 1, 3}; });
    CHECK(starts_with(f, "mesh domain 1: the ghost mask has 3 entries, the domain 4 cells"));
  }
  SECTION("dims that do not match the vertices") {
    const ElementList m = grid_hexes(2, 2, 2, Vec3(0.0), Vec3(1.0), one);
    OwnedMesh om = curvilinear(m, 2, 2, 2);
    om.mesh.domains[0].dims[2] = 4;
    CHECK(starts_with(fault(om.mesh), "mesh domain 0: curvilinear dims 3x3x4 need 36 vertices"));
  }
  SECTION("unsupported shapes and dtypes") {
    CHECK(starts_with(fault_in_second([](O&, D& d) { d.shape = tessera::Shape::Wedge; }),
                      "mesh domain 1: wedge elements are not supported yet"));
    CHECK(starts_with(fault_in_second([](O&, D& d) { d.coords.dtype = tessera::DType::UInt16; }),
                      "mesh domain 1: coordinates must be float32 or float64"));
    CHECK(starts_with(fault_in_second([](O&, D& d) { d.connectivity = nullptr; }),
                      "mesh domain 1: the connectivity array is null"));
  }
  SECTION("nothing to render") {
    CHECK(fault(tessera::Mesh{}) == "mesh: no domain");
    const ElementList m = grid_hexes(1, 1, 1, Vec3(0.0), Vec3(1.0), one);
    OwnedMesh om = one_domain(m);
    const std::uint8_t ghost = 1;
    om.mesh.domains[0].ghosts = {&ghost, 1, 1};
    CHECK(fault(om.mesh) == "mesh: no real (non-ghost) cell in any domain");
  }
  SECTION("prepare refuses it too") {
    const ElementList m = grid_hexes(1, 1, 1, Vec3(0.0), Vec3(1.0), one);
    OwnedMesh om = one_domain(m);
    om.owned[0]->y[2] = std::nan("");
    CHECK_THROWS_WITH(tessera::prepare(om.mesh, tessera::SceneDesc{}),
                      Catch::StartsWith("mesh domain 0: element 0: vertex 2 has a non-finite coordinate"));
  }
}

TEST_CASE("mesh: arrays in unmapped or no-access memory are named before anything reads them", "[mesh]") {
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  void* gone = ::mmap(nullptr, page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  REQUIRE(gone != MAP_FAILED);
  REQUIRE(::munmap(gone, page) == 0);
  void* locked = ::mmap(nullptr, page, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  REQUIRE(locked != MAP_FAILED);
  const auto named = [](const std::string& e, const std::string& what) {
    INFO(e);
    CHECK(starts_with(e, "mesh domain 1: " + what + " at "));
    CHECK(e.find("is not readable host memory: byte 0 of its") != std::string::npos);
  };
  named(fault_in_second([&](OwnedDomain&, tessera::MeshDomain& d) { d.coords.y = gone; }), "coords.y");
  named(fault_in_second([&](OwnedDomain&, tessera::MeshDomain& d) { d.connectivity = locked; }), "the connectivity");
  named(fault_in_second([&](OwnedDomain&, tessera::MeshDomain& d) { d.field.data = gone; }), "the field");
  // ... and the arrays' reuse check (prepare's `reuse`) finds them too
  ElementList m = grid_hexes(2, 2, 2, Vec3(0.0), Vec3(1.0), one);
  OwnedMesh om = one_domain(m);
  om.mesh.domains[0].coords.x = locked;
  CHECK_THROWS_WITH(tessera::check_mesh_arrays(om.mesh), Catch::Contains("coords.x at"));
  ::munmap(locked, page);
}

TEST_CASE("mesh: the checks take linear time on a large mesh", "[mesh]") {
  // 40^3 hexes (64000 elements) with one bad index at the very end: found in one pass
  ElementList m = grid_hexes(40, 40, 40, Vec3(0.0), Vec3(1.0), one);
  OwnedMesh om = one_domain(m);
  om.owned[0]->conn32.back() = -7;
  CHECK(starts_with(fault(om.mesh), "mesh domain 0: element 63999: vertex index -7 (entry 7)"));
}

TEST_CASE("mesh: the check runs over threads and names the lowest faulty element under any thread count", "[mesh]") {
  // 40^3 hexes with faults at three places (an index, an inverted cell, a NaN vertex): the
  // message is the one for the lowest of them, however many threads run the check
  ElementList m = grid_hexes(40, 40, 40, Vec3(0.0), Vec3(1.0), one);
  OwnedMesh om = one_domain(m);
  std::int32_t* conn = om.owned[0]->conn32.data();
  conn[8 * 61000 + 2] = 1 << 30;
  for (int k = 0; k < 4; ++k) std::swap(conn[8 * 23456 + k], conn[8 * 23456 + 4 + k]);
  const std::string want = "mesh domain 0: element 23456: hex is inverted";
  for (const int threads : {1, 2, 3, 8}) {
    tbb::task_arena arena(threads);
    std::string got;
    arena.execute([&] { got = fault(om.mesh); });
    INFO(threads << " threads");
    CHECK(starts_with(got, want));
  }
  om.owned[0]->z[conn[8 * 40000 + 5]] = std::numeric_limits<double>::infinity();
  CHECK(starts_with(fault(om.mesh), want));
  for (int k = 0; k < 4; ++k) std::swap(conn[8 * 23456 + k], conn[8 * 23456 + 4 + k]);  // mended
  CHECK(starts_with(fault(om.mesh), "mesh domain 0: element 40000: "));
  CHECK_THAT(fault(om.mesh), Catch::Contains("non-finite coordinate"));

  // A curvilinear grid takes its first real cell's handedness: mirrored, it passes; one cell
  // of the other handedness is named, whichever thread meets it
  ElementList mirrored =
      grid_hexes(30, 30, 30, Vec3(0.0), Vec3(1.0), one, [](const Vec3& p) { return Vec3(-p.x, p.y, p.z); });
  OwnedMesh cm = curvilinear(mirrored, 30, 30, 30);
  CHECK(fault(cm.mesh).empty());
  cm.owned[0]->x[15 + 31 * (15 + 31 * 15)] -= 2.5;  // an inner vertex pushed through its neighbours
  std::string alone;
  tbb::task_arena(1).execute([&] { alone = fault(cm.mesh); });
  CHECK_THAT(alone, Catch::Contains("mesh domain 0: element ") && Catch::Contains(": hex is "));
  for (const int threads : {2, 5}) {
    std::string got;
    tbb::task_arena(threads).execute([&] { got = fault(cm.mesh); });
    CHECK(got == alone);
  }
}
