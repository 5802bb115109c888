// The refusals of tessera_execute_domains' descriptors name the element, axis or index at
// fault, in the data's own terms (cell or vertex), without overflow (domain_binding.h).
#include "data/domain_binding.h"
#include "domain_cuts.h"
#include "insitu_test_support.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
using tessera_test::CutBox;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

const Dims kG{12, 10, 8};

/// bind_domains' message, or "" when it accepts.
std::string refusal(const tessera_mesh& mesh, const std::vector<tessera_domain>& domains) {
  try {
    bind_domains(&mesh, domains.data(), static_cast<std::int64_t>(domains.size()), "density", "view");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST_CASE("domain messages: the 2^40 check names the axis and interval of the smallest spacing",
          "[insitu][domains][errors]") {
  // j has one interval of 1e-13 (coords[1][4] - [3]); i spans [-0.5, 0.5], beyond 2^40 of it.
  // The message blames i's extent and names j's interval as the smallest spacing
  std::vector<double> y = tessera_test::stretched_axis(kG[1], 0.0);
  y[4] = y[3] + 1e-13;
  tessera_mesh mesh = tessera_test::unit_mesh(kG, TESSERA_VERTEX);
  mesh.coords[1] = y.data();
  const std::string e = refusal(mesh, {});
  INFO(e);
  CHECK_THAT(e, Contains("mesh: along i it spans [-0.5, 0.5], beyond 2^40 times the mesh's smallest spacing") &&
                    Contains("is coords[1] (j)[4] - [3])"));
  // A uniform axis with the smallest spacing, and levels: named as the spacing / the ratios
  tessera_mesh fine = tessera_test::unit_mesh(kG, TESSERA_VERTEX);
  static const int ratios[2] = {4, 4};
  fine.nlevels = 3;
  fine.refinement = ratios;
  fine.spacing[2] = 1e-12;
  const std::string f = refusal(fine, {});
  INFO(f);
  CHECK_THAT(f, Contains("mesh: along i it spans") && Contains("is spacing[2] (k) / 16 at the finest level)"));
}

TEST_CASE("domain messages: cell data is described in cells, vertex data in vertices", "[insitu][domains][errors]") {
  for (const tessera_association assoc : {TESSERA_CELL, TESSERA_VERTEX}) {
    const bool cells = assoc == TESSERA_CELL;
    INFO((cells ? "cell data" : "vertex data"));
    const HeldDomains one(kG, {CutBox{{0, 0, 0}, kG}});
    const tessera_mesh mesh = tessera_test::unit_mesh(kG, assoc);
    // Ghosts that leave nothing real
    std::vector<tessera_domain> d = one.of_rank(0, 1);
    tessera_field f = d[0].fields[0];
    f.ghosts_lo[1] = f.dims[1] - 1;
    d[0].fields = &f;
    CHECK_THAT(refusal(mesh, d), Contains(cells ? "leave no real cell of dims" : "leave no real vertex of dims"));
    // Real elements past the mesh
    d = one.of_rank(0, 1);
    d[0].offset[2] = 3;
    CHECK_THAT(refusal(mesh, d), Contains(cells ? "real cells [3..11) along k" : "real vertices [3..11) along k"));
  }
}

TEST_CASE("domain messages: an offset near INT64_MAX prints the interval it claims, not a wrapped one",
          "[insitu][domains][errors]") {
  const HeldDomains one(kG, {CutBox{{0, 0, 0}, kG}});
  const tessera_mesh mesh = tessera_test::unit_mesh(kG, TESSERA_CELL);
  std::vector<tessera_domain> d = one.of_rank(0, 1);
  const std::int64_t big = std::numeric_limits<std::int64_t>::max() - 2;
  d[0].offset[0] = big;
  const std::string e = refusal(mesh, d);
  INFO(e);
  // 12 cells from INT64_MAX - 2: the interval ends at 2^63 + 9, past INT64_MAX
  CHECK_THAT(e, Contains("real cells [9223372036854775805..9223372036854775817) along i") &&
                    Contains("leave the mesh's [0..12)"));
}

TEST_CASE("every published field's descriptors are checked at a call that renders, the render's or not",
          "[insitu][domains][errors]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("main", "{every: 2}")));
  constexpr int n = 8;
  const std::vector<float> values = to_float(blob_values(n));
  const tessera_field density = dense_field("density", values.data(), n);
  tessera_field pressure = dense_field("pressure", values.data(), n);
  pressure.ghosts_lo[2] = n;  // no real element left: never rendered, still wrong

  // tessera_execute: the grid's fields
  Adapter a;
  a.set_quiet(true);
  REQUIRE(a.open(cfg) == TESSERA_OK);
  const tessera_field both[2] = {density, pressure};
  CHECK(a.execute(1, 0.1, unit_grid(n), {both, 2}) == TESSERA_OK);  // nothing fires: nothing read
  CHECK(a.execute(2, 0.2, unit_grid(n), {both, 2}) == TESSERA_ERROR_DATA);
  CHECK_THAT(a.last_error(), Contains("field 'pressure'") && Contains("ghost layers along k"));
  CHECK(a.execute(4, 0.4, unit_grid(n), {&density, 1}) == TESSERA_OK);
  a.close();

  // tessera_execute_domains: every domain's fields
  const HeldDomains two(kG, {CutBox{{0, 0, 0}, {6, 10, 8}}, CutBox{{6, 0, 0}, {6, 10, 8}}});
  const tessera_mesh mesh = tessera_test::unit_mesh(kG, TESSERA_CELL);
  std::vector<tessera_domain> d = two.of_rank(0, 1);
  std::vector<std::vector<tessera_field>> lists(d.size());
  for (std::size_t q = 0; q < d.size(); ++q) {
    lists[q] = {d[q].fields[0], d[q].fields[0]};
    lists[q][1].name = "pressure";
    d[q].fields = lists[q].data();
    d[q].nfields = 2;
  }
  CHECK(refusal(mesh, d).empty());
  lists[1][1].byte_strides[0] = 0;  // domain 1's pressure: a zero stride
  CHECK_THAT(refusal(mesh, d), Contains("domain 1: field 'pressure'") && Contains("stride"));
  lists[1][1] = lists[1][0];
  lists[1][1].name = "pressure";
  lists[1][1].ghosts_hi[0] = 9;  // domain 1's pressure: ghosts leave no real cell
  CHECK_THAT(refusal(mesh, d), Contains("domain 1: field 'pressure'") && Contains("leave no real cell"));
}
