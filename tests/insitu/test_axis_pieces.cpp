// Per-domain rectilinear coordinates (tessera_mesh::axes_from_domains, tessera_domain coords):
// the domains' pieces, ghosts included, assemble into the global axis and render bit-identically
// to the whole axis given once; pieces that disagree where they overlap, a vertex no piece
// covers and a piece of absurd length are refused by rank, domain, axis and index.
#include "axis_pieces.h"
#include "domain_cuts.h"
#include "insitu_test_support.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

const Dims kG{14, 12, 10};

struct Outcome {
  tessera_status status;
  std::string error;
  std::optional<tessera::Image> image;
};

Outcome run(const TempDir& dir, const std::string& name, const tessera_mesh& mesh,
            const std::vector<tessera_domain>& domains) {
  Adapter ad;
  ad.set_quiet(true);
  const std::string renders = render_yaml("view", "{every: 1}", "    integrator: {seed: 3}\n", "density", 24, 2);
  REQUIRE(ad.open(dir.write(name + ".yaml", config_yaml(dir.file(name), renders))) == TESSERA_OK);
  Outcome o;
  o.status = ad.execute_domains(1, 0.0, mesh, domains);
  o.error = ad.last_error();
  if (const tessera::Image* img = ad.last_image("view")) o.image = *img;
  return o;
}

}  // namespace

TEST_CASE("axis pieces: per-domain coordinates assemble into the axis and render as the whole axis does",
          "[insitu][domains][pieces]") {
  TempDir dir;
  for (const tessera_association assoc : {TESSERA_VERTEX, TESSERA_CELL}) {
    INFO((assoc == TESSERA_CELL ? "cell data" : "vertex data"));
    const tessera_test::TestMesh whole(kG, assoc, tessera_test::Axes::StretchedAll);
    const HeldDomains held(kG, tessera_test::seven_cuts(kG));
    const Outcome ref = run(dir, "ref", whole.mesh(), held.of_rank(0, 1));
    REQUIRE(ref.status == TESSERA_OK);
    // j and k from the domains' pieces (cell data: a domain's n cells have n + 1 vertices)
    tessera_mesh mesh = whole.mesh();
    std::vector<tessera_domain> d = held.of_rank(0, 1);
    tessera_test::AxisPieces pieces;
    const int cells = assoc == TESSERA_CELL ? 1 : 0;
    for (const int a : {1, 2}) {
      const std::vector<double> axis(mesh.coords[a], mesh.coords[a] + kG[a] + cells);
      pieces.give(d, a, axis, 1, cells == 1);
      mesh.coords[a] = nullptr;
      mesh.spacing[a] = 0.0;  // ignored for an axis in pieces
    }
    mesh.axes_from_domains = 2 | 4;
    const Outcome pieced = run(dir, "pieced", mesh, d);
    INFO(pieced.error);
    REQUIRE(pieced.status == TESSERA_OK);
    CHECK(same_pixels(*ref.image, *pieced.image));
  }
}

TEST_CASE("axis pieces: pieces that disagree, a gap, a piece of absurd length are refused by name",
          "[insitu][domains][pieces][errors]") {
  TempDir dir;
  const tessera_test::TestMesh whole(kG, TESSERA_VERTEX, tessera_test::Axes::StretchedY);
  const HeldDomains held(kG, tessera_test::seven_cuts(kG));
  const std::vector<double> axis(whole.mesh().coords[1], whole.mesh().coords[1] + kG[1]);
  tessera_mesh mesh = whole.mesh();
  mesh.coords[1] = nullptr;
  mesh.axes_from_domains = 2;
  std::vector<tessera_domain> d = held.of_rank(0, 1);
  tessera_test::AxisPieces pieces;
  pieces.give(d, 1, axis, 1);
  REQUIRE(run(dir, "ok", mesh, d).status == TESSERA_OK);

  // One value off by an ulp in the high ghost of a domain with a neighbour above along j,
  // where that neighbour's piece holds a real vertex
  std::vector<tessera_domain> bad = d;
  std::size_t victim = d.size();
  for (std::size_t n = 0; n < d.size() && victim == d.size(); ++n)
    if (d[n].offset[1] + (d[n].fields[0].dims[1] - 2) < kG[1]) victim = n;
  REQUIRE(victim < d.size());
  std::vector<double> changed(d[victim].coords[1], d[victim].coords[1] + d[victim].coords_count[1]);
  changed.back() = std::nextafter(changed.back(), 10.0);
  bad[victim].coords[1] = changed.data();
  Outcome o = run(dir, "differ", mesh, bad);
  CHECK(o.status == TESSERA_ERROR_DATA);
  CHECK_THAT(o.error, Contains("coords[1] (j)[") && Contains("domain " + std::to_string(victim)) &&
                          Contains("pieces that overlap must agree bit for bit"));

  // Every piece of the domains at j = 0 gone: the first vertices have no coordinate
  bad = d;
  for (tessera_domain& x : bad)
    if (x.offset[1] == 0) x.coords[1] = nullptr;
  o = run(dir, "gap", mesh, bad);
  CHECK(o.status == TESSERA_ERROR_DATA);
  CHECK_THAT(o.error, Contains("axis j (axes_from_domains): vertices [0..") && Contains("have a coordinate from no "
                                                                                        "domain's piece"));

  // A count far past the axis
  bad = d;
  bad[2].coords_count[1] = std::numeric_limits<std::int64_t>::max();
  o = run(dir, "absurd", mesh, bad);
  CHECK(o.status == TESSERA_ERROR_DATA);
  CHECK_THAT(o.error, Contains("rank 0 domain 2: coords_count[1] = 9223372036854775807, must be in [1, "));
  // The mesh: an axis both in coords and in pieces, pieces with levels
  tessera_mesh both = mesh;
  both.coords[1] = axis.data();
  o = run(dir, "both", both, d);
  CHECK(o.status == TESSERA_ERROR_DATA);
  CHECK_THAT(o.error, Contains("has both coords[1] (j) and bit 2 of axes_from_domains set"));
}
