// Per-field association (tessera_domain::associations, Blueprint's vertex and element fields on
// one topology): a field of the other association sees the same points and cells of the mesh,
// so it renders bit-identically to the same values on a mesh of its own association; the
// associations are checked like the dtypes, within a rank and across ranks.
#include "domain_cuts.h"
#include "insitu_test_support.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <optional>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

struct Outcome {
  tessera_status status;
  std::string error;
  std::optional<tessera::Image> image;
};

Outcome run(const TempDir& dir, const std::string& name, const tessera_mesh& mesh,
            const std::vector<tessera_domain>& domains, const std::string& field = "density") {
  Adapter ad;
  ad.set_quiet(true);
  const std::string renders = render_yaml("view", "{every: 1}", "    integrator: {seed: 3}\n", field, 24, 2);
  REQUIRE(ad.open(dir.write(name + ".yaml", config_yaml(dir.file(name), renders))) == TESSERA_OK);
  Outcome o;
  o.status = ad.execute_domains(1, 0.0, mesh, domains);
  o.error = ad.last_error();
  if (const tessera::Image* img = ad.last_image("view")) o.image = *img;
  return o;
}

/// `held`'s domains with every field given `assoc` (nullptr: none given).
std::vector<tessera_domain> with_associations(std::vector<tessera_domain> d, const tessera_association* assoc) {
  for (tessera_domain& x : d) x.associations = assoc;
  return d;
}

}  // namespace

TEST_CASE("field association: cell data on a vertex mesh and vertex data on a cell mesh render as on their own mesh",
          "[insitu][domains][association]") {
  TempDir dir;
  const Dims cells{11, 9, 7}, vertices{12, 10, 8};  // the same box: 11 x 9 x 7 cells
  static const tessera_association kCell[1] = {TESSERA_CELL}, kVertex[1] = {TESSERA_VERTEX};
  for (const bool cell_field : {true, false}) {
    INFO((cell_field ? "cell data on a vertex mesh" : "vertex data on a cell mesh"));
    const Dims& own = cell_field ? cells : vertices;
    const HeldDomains held(own, tessera_test::seven_cuts(own));
    const std::vector<tessera_domain> plain = held.of_rank(0, 1);
    const tessera_association own_assoc = cell_field ? TESSERA_CELL : TESSERA_VERTEX;
    const Outcome ref = run(dir, "ref", tessera_test::unit_mesh(own, own_assoc), plain);
    REQUIRE(ref.status == TESSERA_OK);
    // The mesh of the other association, the field saying what it is
    const tessera_mesh other =
        cell_field ? tessera_test::unit_mesh(vertices, TESSERA_VERTEX) : tessera_test::unit_mesh(cells, TESSERA_CELL);
    const Outcome mixed = run(dir, "mixed", other, with_associations(plain, cell_field ? kCell : kVertex));
    INFO(mixed.error);
    REQUIRE(mixed.status == TESSERA_OK);
    CHECK(same_pixels(*ref.image, *mixed.image));
    // Without the association the same arrays do not fit the mesh (one element too many or few)
    const Outcome bare = run(dir, "bare", other, plain);
    CHECK(bare.status == TESSERA_ERROR_DATA);  // cells short of the vertices (a gap), or one vertex past the cells
  }
}

TEST_CASE("field association: vertex and cell fields in one call, the render takes its field's",
          "[insitu][domains][association]") {
  TempDir dir;
  const Dims cells{11, 9, 7}, vertices{12, 10, 8};
  const HeldDomains cell_values(cells, {tessera_test::CutBox{{0, 0, 0}, cells}});
  const HeldDomains vertex_values(vertices, {tessera_test::CutBox{{0, 0, 0}, vertices}});
  // One domain holding the whole mesh: 'density' per vertex, 'pressure' per cell
  const std::vector<tessera_domain> whole_cells = cell_values.of_rank(0, 1);
  const std::vector<tessera_domain> whole_vertices = vertex_values.of_rank(0, 1);
  tessera_field pressure = whole_cells[0].fields[0];
  pressure.name = "pressure";
  const tessera_field both[2] = {whole_vertices[0].fields[0], pressure};
  static const tessera_association kMixed[2] = {TESSERA_VERTEX, TESSERA_CELL};
  tessera_domain d = whole_vertices[0];
  d.fields = both;
  d.nfields = 2;
  d.associations = kMixed;
  const tessera_mesh mesh = tessera_test::unit_mesh(vertices, TESSERA_VERTEX);
  const Outcome p = run(dir, "p", mesh, {d}, "pressure");
  INFO(p.error);
  REQUIRE(p.status == TESSERA_OK);
  tessera_domain c = whole_cells[0];
  c.fields = &pressure;
  const Outcome p_ref = run(dir, "p_ref", tessera_test::unit_mesh(cells, TESSERA_CELL), {c}, "pressure");
  REQUIRE(p_ref.status == TESSERA_OK);
  CHECK(same_pixels(*p.image, *p_ref.image));
  const Outcome v = run(dir, "v", mesh, {d}, "density");
  const Outcome v_ref = run(dir, "v_ref", mesh, whole_vertices, "density");
  REQUIRE(v.status == TESSERA_OK);
  CHECK(same_pixels(*v.image, *v_ref.image));
}

TEST_CASE("field association: a value that is no association, or domains that disagree, are refused by name",
          "[insitu][domains][association][errors]") {
  TempDir dir;
  const Dims g{12, 10, 8};
  const HeldDomains held(g, tessera_test::seven_cuts(g));
  const tessera_mesh mesh = tessera_test::unit_mesh(g, TESSERA_VERTEX);
  std::vector<tessera_domain> d = held.of_rank(0, 1);
  static int bogus[1] = {7};
  d[2].associations = reinterpret_cast<const tessera_association*>(bogus);
  Outcome o = run(dir, "bogus", mesh, d);
  CHECK(o.status == TESSERA_ERROR_DATA);
  CHECK_THAT(o.error, Contains("domain 2: associations[0] = 7 (field 'density') is neither TESSERA_VERTEX (0) nor "
                               "TESSERA_CELL (1)"));
  static const tessera_association kCell[1] = {TESSERA_CELL};
  d[2].associations = kCell;  // domain 2 says cell, the others the mesh's vertex
  o = run(dir, "differ", mesh, d);
  CHECK(o.status == TESSERA_ERROR_DATA);
  CHECK_THAT(o.error, Contains("domain 2: field 'density' is cell data (TESSERA_CELL), domain 0's is vertex data"));
  // Cell data on a mesh one vertex thick along an axis: no cell to hold it
  const Dims flat{12, 10, 1};
  const HeldDomains one(Dims{11, 9, 1}, {tessera_test::CutBox{{0, 0, 0}, Dims{11, 9, 1}}});
  tessera_mesh flat_mesh = tessera_test::unit_mesh(flat, TESSERA_VERTEX);
  flat_mesh.spacing[2] = 0.1;
  o = run(dir, "flat", flat_mesh, with_associations(one.of_rank(0, 1), kCell));
  CHECK(o.status == TESSERA_ERROR_DATA);
  CHECK_THAT(o.error, Contains("field 'density' is cell data, but the mesh has 1 vertex along k"));
}
