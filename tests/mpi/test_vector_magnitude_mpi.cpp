// `field: {magnitude: [u, v, w]}` over MPI: 7 uneven domains of three components dealt over 1 to
// 4 ranks (staged per block, then the replica or the bricks of distributed mode) render bit for
// bit as one rank reading the whole grid's components in place; a rank whose components do
// not fit together fails the render on every rank, and none hangs.
#include "domain_cuts.h"
#include "mpi_test_support.h"

#include <tessera/adapter.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <cstring>
#include <deque>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

using namespace tessera_mpi_test;
using tessera_test::CutBox;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

const Dims kG{21, 18, 16};

/// Three components of the same cut, each domain publishing u, v, w (v and w offset copies of
/// the blob field, so the three differ).
struct VectorDomains {
  std::deque<HeldDomains> held;
  std::vector<std::vector<tessera_field>> fields;
  std::vector<tessera_domain> domains;
  VectorDomains(const std::vector<CutBox>& cuts, int ghosts) {
    for (int c = 0; c < 3; ++c) held.emplace_back(kG, cuts, ghosts);
    for (std::size_t n = 0; n < cuts.size(); ++n) {
      tessera_field a = held[0].field(n), b = held[1].field(n), w = held[2].field(n);
      a.name = "u", b.name = "v", w.name = "w";
      fields.push_back({a, b, w});
    }
    for (std::size_t n = 0; n < cuts.size(); ++n) {
      tessera_domain d = held[0].domain(n);
      d.fields = fields[n].data();
      d.nfields = 3;
      domains.push_back(d);
    }
  }
  std::vector<tessera_domain> of_rank(int rank, int n) const {
    std::vector<tessera_domain> out;
    for (std::size_t d = 0; d < domains.size(); ++d)
      if (static_cast<int>(d % static_cast<std::size_t>(n)) == rank) out.push_back(domains[d]);
    return out;
  }
};

std::string config_text(const std::string& out, const std::string& distribution) {
  return "tessera:\n  output_dir: " + out + "\n  distribution: " + distribution +
         "\n  threads: 1\n"
         "renders:\n"
         "  - name: view\n"
         "    field: {magnitude: [u, v, w]}\n"
         "    image: {width: 40, height: 30, spp: 2}\n"
         "    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: 3.2}}, look_at: center, "
         "up: [0, 0, 1], fov: 30}\n"
         "    transfer_function: {range: auto, density_scale: 30, opacity: [[0, 0], [1, 1]], diffuse: viridis}\n"
         "    lights: [{type: sphere, position: [2, -1, 3], radius: 0.3, intensity: 10}]\n"
         "    integrator: {scattering: multiple, max_bounces: 4, seed: 5}\n"
         "    output: {file: \"{name}\", formats: [exr]}\n";
}

struct Run {
  tessera_status status = TESSERA_OK;  ///< the same on every member (-1 if they differed)
  std::string error;
  std::optional<tessera::Image> image;
};

/// Step 1 on the first n ranks; `break_rank` >= 0: that rank's first domain publishes w one
/// element short along i.
Run run_on(int n, const std::string& cfg, const VectorDomains& v, int break_rank = -1) {
  FirstRanks sub(n);
  Run run;
  int status = TESSERA_OK;
  if (sub.member()) {
    int r = 0;
    MPI_Comm_rank(sub.comm(), &r);
    tessera::insitu::Adapter ad;
    status = ad.open(cfg, MPI_Comm_c2f(sub.comm()));
    ad.set_quiet(true);
    if (status == TESSERA_OK) {
      std::vector<tessera_domain> mine = v.of_rank(r, n);
      std::vector<tessera_field> broken;
      if (r == break_rank && !mine.empty()) {
        broken.assign(mine[0].fields, mine[0].fields + 3);
        broken[2].dims[0] -= 1;
        mine[0].fields = broken.data();
      }
      const tessera_mesh mesh = tessera_test::unit_mesh(kG, TESSERA_VERTEX);
      status = ad.execute_domains(1, 0.0, mesh, mine);
      if (r == 0) {
        run.error = ad.last_error();
        if (const tessera::Image* img = ad.last_image("view")) run.image = *img;
      }
    }
  }
  run.status = static_cast<tessera_status>(sub.agreed_status(status));
  return run;
}

std::string write_config(const SharedTempDir& dir, const std::string& name, const std::string& distribution) {
  const std::string out = dir.file(name);
  if (world_rank() == 0) std::ofstream(out + ".yaml") << config_text(out, distribution);
  MPI_Barrier(MPI_COMM_WORLD);
  return out + ".yaml";
}

}  // namespace

TEST_CASE("magnitude: 7 domains staged over 1 to 4 ranks render as one rank reading the components in place",
          "[mpi][magnitude][determinism]") {
  SharedTempDir dir;
  const VectorDomains whole({CutBox{{0, 0, 0}, kG}}, 0);
  const VectorDomains seven(tessera_test::seven_cuts(kG), 1);
  for (const std::string mode : {"replicated", "distributed"}) {
    const std::string cfg = write_config(dir, mode, mode);
    const Run ref = run_on(1, cfg, whole);  // one whole domain on one rank: in place
    INFO(mode << ": " << ref.error);
    REQUIRE(ref.status == TESSERA_OK);
    bool ok = true;
    for (int n : sizes_up_to_world()) {
      const Run r = run_on(n, cfg, seven);
      INFO(n << " ranks: " << r.error);
      REQUIRE(r.status == TESSERA_OK);
      if (world_rank() == 0) {
        const bool same =
            r.image && ref.image && r.image->rgba.size() == ref.image->rgba.size() &&
            std::memcmp(r.image->rgba.data(), ref.image->rgba.data(), r.image->rgba.size() * sizeof(float)) == 0;
        CHECK(same);
        ok = ok && same;
      }
    }
    REQUIRE(all_ranks(ok));
  }
}

TEST_CASE("magnitude: a rank whose components do not fit together fails the render on every rank",
          "[mpi][magnitude][errors]") {
  SharedTempDir dir;
  const VectorDomains seven(tessera_test::seven_cuts(kG), 1);
  const std::string cfg = write_config(dir, "broken", "replicated");
  const int n = std::min(world_size(), 3);
  const Run r = run_on(n, cfg, seven, n - 1);
  CHECK(r.status == TESSERA_ERROR_DATA);
  if (world_rank() == 0) CHECK_THAT(r.error, Catch::Matchers::Contains("fields 'u' and 'w', differ in domain"));
}
