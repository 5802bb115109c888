// tessera_execute_mesh_domains on one rank: a warped box of hexahedra published as a
// curvilinear grid, as unstructured hexahedra and cut into blocks in any order renders the
// same image bit for bit; as tetrahedra it renders too; cell data; the descriptors' faults are
// refused by name with TESSERA_ERROR_DATA, and nothing is written. (Several ranks: tests/mpi.)
#include "insitu_test_support.h"
#include "mesh_blocks.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <deque>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
using tessera_test::MeshBlock;
using Form = tessera_test::MeshBlock::Form;

namespace {

const std::int64_t kN[3] = {9, 8, 10};

struct Outcome {
  tessera_status status;
  std::string error;
  std::optional<tessera::Image> image;
};

Outcome run(const TempDir& dir, const std::string& name, const std::vector<tessera_mesh_domain>& domains,
            const std::string& field = "f") {
  Adapter ad;
  ad.set_quiet(true);
  const std::string tf = "    transfer_function: {range: auto, density_scale: {optical_depth: 12}, "
                         "opacity: [[0, 0], [1, 1]], diffuse: viridis}\n";
  REQUIRE(ad.open(dir.write(name + ".yaml", config_yaml(dir.file(name), render_yaml("view", "", tf, field, 32, 2)))) ==
          TESSERA_OK);
  Outcome o;
  o.status = ad.execute_mesh_domains(1, 0.0, domains);
  o.error = ad.last_error();
  if (const tessera::Image* img = ad.last_image("view")) o.image = *img;
  return o;
}

/// The box cut along k at `cuts` (cell layers), as `form`.
struct Cut {
  std::deque<MeshBlock> blocks;
  std::vector<tessera_mesh_domain> domains;
  Cut(const std::vector<std::int64_t>& cuts, Form form, bool cell_data = false) {
    for (std::size_t n = 0; n + 1 < cuts.size(); ++n) blocks.emplace_back(kN, cuts[n], cuts[n + 1]);
    for (MeshBlock& b : blocks) domains.push_back(b.domain(form, cell_data));
  }
};

}  // namespace

TEST_CASE("mesh domains: curvilinear, unstructured hexahedra and any cut render the same image", "[insitu][mesh]") {
  TempDir dir;
  for (const bool cell_data : {false, true}) {
    INFO((cell_data ? "cell data" : "vertex data"));
    Cut curvilinear({0, 9}, Form::Curvilinear, cell_data);
    const Outcome ref = run(dir, "curv", curvilinear.domains);
    INFO(ref.error);
    REQUIRE(ref.status == TESSERA_OK);
    REQUIRE(ref.image);
    CHECK(mean_luminance(*ref.image) > 0.0);
    Cut hexes({0, 9}, Form::Hexes, cell_data);
    const Outcome h = run(dir, "hex", hexes.domains);
    REQUIRE(h.status == TESSERA_OK);
    CHECK(same_pixels(*ref.image, *h.image));
    // Three blocks, curvilinear and unstructured mixed, listed backwards
    Cut three({0, 3, 7, 9}, Form::Hexes, cell_data);
    Cut curv3({0, 3, 7, 9}, Form::Curvilinear, cell_data);
    std::vector<tessera_mesh_domain> mixed = {three.domains[2], curv3.domains[1], three.domains[0]};
    const Outcome m = run(dir, "mixed", mixed);
    INFO(m.error);
    REQUIRE(m.status == TESSERA_OK);
    CHECK(same_pixels(*ref.image, *m.image));
  }
  // Tetrahedra of the same cells: a picture too (another interpolation: not the same bits)
  Cut tets({0, 4, 9}, Form::Tets);
  const Outcome t = run(dir, "tets", tets.domains);
  INFO(t.error);
  REQUIRE(t.status == TESSERA_OK);
  CHECK(mean_luminance(*t.image) > 0.0);
}

TEST_CASE("mesh domains: faults are refused by domain and element, nothing is written", "[insitu][mesh][errors]") {
  TempDir dir;
  const auto refused = [&](const std::string& name, const std::vector<tessera_mesh_domain>& d, const std::string& what,
                           const std::string& field = "f") {
    const Outcome o = run(dir, name, d, field);
    INFO(o.error);
    CHECK(o.status == TESSERA_ERROR_DATA);
    CHECK_THAT(o.error, Contains(what));
    CHECK_FALSE(std::filesystem::exists(dir.file(name) + "/view_000001.exr"));
  };
  Cut cut({0, 4, 9}, Form::Hexes);
  std::vector<tessera_mesh_domain> d = cut.domains;
  cut.blocks[1].hexes[8 * 5 + 3] = 100000;  // element 5 of domain 1
  refused("index", d, "domain 1");
  refused("index2", d, "element 5");
  cut.blocks[1].hexes[8 * 5 + 3] = cut.blocks[1].hexes[8 * 5 + 0];
  refused("degenerate", d, "element 5");
  Cut ok({0, 4, 9}, Form::Hexes);
  d = ok.domains;
  d[0].coords.dtype = TESSERA_INT32;
  refused("coord_dtype", d, "domain 0: coords.dtype");
  d = ok.domains;
  d[1].index_dtype = TESSERA_FLOAT32;
  refused("index_dtype", d, "domain 1: index_dtype");
  d = ok.domains;
  d[1].shape = TESSERA_WEDGE;
  refused("wedge", d, "wedge");
  d = ok.domains;
  d[0].association = TESSERA_CELL;  // the vertex array is then the wrong length, and domain 1 disagrees
  refused("assoc", d, "domain 1: is vertex data, domain 0 cell data");
  d = ok.domains;
  d[0].ghost_field = "g";
  refused("ghost", d, "ghost_field 'g' is not among the domain's fields");
  ok.blocks[0].x[3] = std::nan("");
  refused("nan", ok.domains, "domain 0");
  refused("unknown", Cut({0, 9}, Form::Hexes).domains, "field 'p'", "p");
  refused("none", {}, "no rank passed a domain");
  refused("magnitude", Cut({0, 9}, Form::Hexes).domains, "magnitude", "{magnitude: [f, f, f]}");
}

TEST_CASE("mesh domains: a mesh whose tables would pass memory_limit_mb is refused before they are built",
          "[insitu][mesh][limits]") {
  TempDir dir;
  // 60 x 60 x 40 vertices: 135 759 cells, 65 MB of lookup tables at most, over a 16 MB limit
  const std::int64_t n[3] = {60, 60, 40};
  MeshBlock big(n, 0, 39);
  const std::vector<tessera_mesh_domain> d = {big.domain(Form::Curvilinear)};
  Adapter ad;
  ad.set_quiet(true);
  REQUIRE(ad.open(dir.write("limit.yaml", config_yaml(dir.file("limit"), render_yaml("view", "", "", "f", 16, 1),
                                                      "  memory_limit_mb: 16\n"))) == TESSERA_OK);
  CHECK(ad.execute_mesh_domains(1, 0.0, d) == TESSERA_ERROR_RENDER);
  CHECK_THAT(ad.last_error(), Contains("mesh lookup tables"));
  CHECK_THAT(ad.last_error(), Contains("tessera.memory_limit_mb = 16 MiB"));
}

TEST_CASE("mesh domains: the lookup structure is reused within a call, and across calls after mesh_unchanged",
          "[insitu][mesh][reuse]") {
  TempDir dir;
  Cut cut({0, 4, 9}, Form::Hexes);
  const std::string tf = "    transfer_function: {range: [0, 1], density_scale: 20, opacity: [[0, 0], [1, 1]]}\n";
  const std::string renders = render_yaml("a", "", tf, "f", 24, 2) + render_yaml("b", "", tf, "f", 24, 2);
  Adapter ad;
  ad.set_quiet(true);
  REQUIRE(ad.open(dir.write("reuse.yaml", config_yaml(dir.file("reuse"), renders))) == TESSERA_OK);
  const auto reused = [&](const char* name) {
    for (const RenderResult& r : ad.last_results())
      if (r.name == name) return r.mesh_layout_reused;
    FAIL("no result for " << name);
    return false;
  };
  REQUIRE(ad.execute_mesh_domains(1, 0.0, cut.domains) == TESSERA_OK);
  CHECK_FALSE(reused("a"));
  CHECK(reused("b"));  // the same call's mesh
  const tessera::Image first = *ad.last_image("a");
  // Other values at step 2, no promise: the geometry hashes as the last one's, so the
  // structure is reused all the same, and the image is a fresh adapter's bit for bit
  for (MeshBlock& b : cut.blocks)
    for (double& v : b.vertex_values) v = 1.0 - v;
  REQUIRE(ad.execute_mesh_domains(2, 0.1, cut.domains) == TESSERA_OK);
  CHECK(reused("a"));
  const tessera::Image built = *ad.last_image("a");
  CHECK_FALSE(same_pixels(first, built));
  {
    Adapter fresh;
    fresh.set_quiet(true);
    REQUIRE(fresh.open(dir.write("fresh.yaml", config_yaml(dir.file("fresh"), renders))) == TESSERA_OK);
    REQUIRE(fresh.execute_mesh_domains(2, 0.1, cut.domains) == TESSERA_OK);
    CHECK(same_pixels(built, *fresh.last_image("a")));
  }
  // Found by its hash, an index out of range (no promise) hashes otherwise: checked again and
  // refused by domain and element, nothing kept of it; put back, found again
  {
    auto& entry = cut.blocks[1].hexes[8 * 5 + 3];
    const auto kept = entry;
    entry = 100000;
    CHECK(ad.execute_mesh_domains(2, 0.1, cut.domains) == TESSERA_ERROR_DATA);
    CHECK_THAT(ad.last_error(), Contains("mesh domain 1: element 5"));
    entry = kept;
    REQUIRE(ad.execute_mesh_domains(2, 0.1, cut.domains) == TESSERA_OK);
    CHECK(reused("a"));
    CHECK(same_pixels(built, *ad.last_image("a")));
  }
  // With the promise, reused; the image as a build gives it
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);
  REQUIRE(ad.execute_mesh_domains(2, 0.1, cut.domains) == TESSERA_OK);
  CHECK(reused("a"));
  CHECK(same_pixels(built, *ad.last_image("a")));
  // A vertex moved, no promise: built again; the next call with it unmoved is found again
  // (the hash is the one of the geometry the structure was built over)
  double& x = cut.blocks[1].x[7];
  const double x0 = x;
  x += 1e-3;
  REQUIRE(ad.execute_mesh_domains(3, 0.2, cut.domains) == TESSERA_OK);
  CHECK_FALSE(reused("a"));
  REQUIRE(ad.execute_mesh_domains(4, 0.25, cut.domains) == TESSERA_OK);
  CHECK(reused("a"));
  x = x0;
  REQUIRE(ad.execute_mesh_domains(5, 0.25, cut.domains) == TESSERA_OK);
  CHECK_FALSE(reused("a"));
  // A mesh of other shapes is built again even after the promise
  Cut other({0, 9}, Form::Hexes);
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);
  REQUIRE(ad.execute_mesh_domains(4, 0.3, other.domains) == TESSERA_OK);
  CHECK_FALSE(reused("a"));
  // Built under a promise (not hashed before), it is hashed after the build: the next call
  // finds it without the promise, and renders a fresh adapter's bits
  REQUIRE(ad.execute_mesh_domains(5, 0.35, other.domains) == TESSERA_OK);
  CHECK(reused("a"));
  {
    Adapter fresh;
    fresh.set_quiet(true);
    REQUIRE(fresh.open(dir.write("fresh2.yaml", config_yaml(dir.file("fresh2"), renders))) == TESSERA_OK);
    REQUIRE(fresh.execute_mesh_domains(5, 0.35, other.domains) == TESSERA_OK);
    CHECK(same_pixels(*ad.last_image("a"), *fresh.last_image("a")));
  }
}

TEST_CASE("mesh domains: after mesh_unchanged an index out of range is still refused, the shapes are the promise",
          "[insitu][mesh][reuse][errors]") {
  TempDir dir;
  Cut cut({0, 4, 9}, Form::Hexes);
  const std::string tf = "    transfer_function: {range: [0, 1], density_scale: 20, opacity: [[0, 0], [1, 1]]}\n";
  Adapter ad;
  ad.set_quiet(true);
  REQUIRE(ad.open(dir.write("promise.yaml", config_yaml(dir.file("promise"), render_yaml("a", "", tf, "f", 24, 2)))) ==
          TESSERA_OK);
  REQUIRE(ad.execute_mesh_domains(1, 0.0, cut.domains) == TESSERA_OK);
  // A broken promise that would read outside the arrays: refused by domain and element
  auto& entry = cut.blocks[1].hexes[8 * 5 + 3];
  const auto kept = entry;
  entry = 100000;
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);
  CHECK(ad.execute_mesh_domains(2, 0.1, cut.domains) == TESSERA_ERROR_DATA);
  CHECK_THAT(ad.last_error(), Contains("mesh domain 1: element 5: vertex index 100000"));
  CHECK_FALSE(std::filesystem::exists(dir.file("promise") + "/a_000002.exr"));
  // A degenerate element is a fault of the shapes: not looked at under the promise (the
  // layout's build checked them), refused again without it
  entry = cut.blocks[1].hexes[8 * 5 + 0];
  REQUIRE(ad.execute_mesh_domains(3, 0.2, Cut({0, 4, 9}, Form::Hexes).domains) == TESSERA_OK);
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);
  CHECK(ad.execute_mesh_domains(4, 0.3, cut.domains) == TESSERA_OK);
  CHECK(ad.execute_mesh_domains(5, 0.4, cut.domains) == TESSERA_ERROR_DATA);
  CHECK_THAT(ad.last_error(), Contains("element 5: hex is degenerate"));
  entry = kept;
  CHECK(ad.execute_mesh_domains(6, 0.5, cut.domains) == TESSERA_OK);
}

TEST_CASE("mesh domains: mesh_unchanged means as at the last call even one at which no render fired",
          "[insitu][mesh][reuse]") {
  // Step 3 moves a vertex and renders nothing (every: 2); the promise before step 4 is true of
  // step 3, whose geometry is not the structure's (built at step 2): step 4 must build again
  // and render what a fresh adapter renders
  TempDir dir;
  Cut cut({0, 4, 9}, Form::Hexes);
  const std::string tf = "    transfer_function: {range: [0, 1], density_scale: 20, opacity: [[0, 0], [1, 1]]}\n";
  const std::string renders = render_yaml("a", "{every: 2}", tf, "f", 24, 2);
  Adapter ad;
  ad.set_quiet(true);
  REQUIRE(ad.open(dir.write("chain.yaml", config_yaml(dir.file("chain"), renders))) == TESSERA_OK);
  const auto reused = [&] {
    REQUIRE(ad.last_results().size() == 1);
    return ad.last_results()[0].mesh_layout_reused;
  };
  REQUIRE(ad.execute_mesh_domains(2, 0.0, cut.domains) == TESSERA_OK);
  CHECK_FALSE(reused());
  for (std::size_t v = 0; v < cut.blocks[1].x.size(); v += 5) cut.blocks[1].x[v] += 0.02;  // a fifth of a cell
  REQUIRE(ad.execute_mesh_domains(3, 0.1, cut.domains) == TESSERA_OK);
  CHECK(ad.last_results().empty());
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);  // true of step 3
  REQUIRE(ad.execute_mesh_domains(4, 0.2, cut.domains) == TESSERA_OK);
  CHECK_FALSE(reused());
  const tessera::Image moved = *ad.last_image("a");
  {
    Adapter fresh;
    fresh.set_quiet(true);
    REQUIRE(fresh.open(dir.write("fresh.yaml", config_yaml(dir.file("fresh"), renders))) == TESSERA_OK);
    REQUIRE(fresh.execute_mesh_domains(4, 0.2, cut.domains) == TESSERA_OK);
    CHECK(same_pixels(moved, *fresh.last_image("a")));
  }
  // Promised at a call that renders nothing and at the next: the chain holds, reused
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);
  REQUIRE(ad.execute_mesh_domains(5, 0.3, cut.domains) == TESSERA_OK);
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);
  REQUIRE(ad.execute_mesh_domains(6, 0.4, cut.domains) == TESSERA_OK);
  CHECK(reused());
}
