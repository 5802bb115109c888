// tessera_execute_mesh_domains over MPI: a warped box of hexahedra cut into 5 blocks (curvilinear
// and unstructured alternating) dealt round robin over 1 to 4 ranks, a rank holding none,
// renders bit for bit as one rank's single curvilinear domain; a bad element or a field that
// ranks publish differently fails the render on every rank with TESSERA_ERROR_DATA, none hangs.
#include "mesh_blocks.h"
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
using tessera_test::MeshBlock;
using Form = tessera_test::MeshBlock::Form;

namespace {

const std::int64_t kN[3] = {10, 9, 12};

struct Blocks {
  std::deque<MeshBlock> blocks;
  std::vector<tessera_mesh_domain> domains;
  Blocks(const std::vector<std::int64_t>& cuts, bool mixed) {
    for (std::size_t n = 0; n + 1 < cuts.size(); ++n) blocks.emplace_back(kN, cuts[n], cuts[n + 1]);
    for (std::size_t n = 0; n < blocks.size(); ++n)
      domains.push_back(blocks[n].domain(mixed && n % 2 ? Form::Hexes : Form::Curvilinear));
  }
};

struct Run {
  tessera_status status = TESSERA_OK;  ///< the same on every member (-1 if they differed)
  std::string error;
  std::optional<tessera::Image> image;
};

/// Step 2 on the first n ranks, domain d on rank d % n (none on rank 1 when `skip1`);
/// `edit` changes a rank's domains first.
template <class Edit>
Run run_on(int n, const std::string& cfg, const Blocks& b, bool skip1, Edit&& edit) {
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
      std::vector<tessera_mesh_domain> mine;
      const int holders = skip1 && n > 2 ? n - 1 : n;
      const int slot = skip1 && n > 2 ? (r == 1 ? -1 : r == 0 ? 0 : r - 1) : r;
      for (std::size_t d = 0; d < b.domains.size(); ++d)
        if (static_cast<int>(d % static_cast<std::size_t>(holders)) == slot) mine.push_back(b.domains[d]);
      edit(r, mine);
      status = ad.execute_mesh_domains(2, 0.5, mine);
      if (r == 0) {
        run.error = ad.last_error();
        if (const tessera::Image* img = ad.last_image("view")) run.image = *img;
      }
    }
  }
  run.status = static_cast<tessera_status>(sub.agreed_status(status));
  return run;
}

std::string write_config(const SharedTempDir& dir, const std::string& name) {
  const std::string out = dir.file(name);
  if (world_rank() == 0)
    std::ofstream(out + ".yaml") << "tessera:\n  output_dir: " << out
                                 << "\n  threads: 1\n"
                                    "renders:\n"
                                    "  - name: view\n"
                                    "    field: f\n"
                                    "    image: {width: 40, height: 32, spp: 2}\n"
                                    "    integrator: {scattering: multiple, max_bounces: 4, seed: 9}\n"
                                    "    output: {file: \"{name}\", formats: [exr]}\n";
  MPI_Barrier(MPI_COMM_WORLD);
  return out + ".yaml";
}

bool same(const std::optional<tessera::Image>& a, const std::optional<tessera::Image>& b) {
  return a && b && a->rgba.size() == b->rgba.size() &&
         std::memcmp(a->rgba.data(), b->rgba.data(), a->rgba.size() * sizeof(float)) == 0;
}

}  // namespace

TEST_CASE("mesh domains: 5 blocks over 1 to 4 ranks render as one rank's single domain", "[mpi][mesh][determinism]") {
  SharedTempDir dir;
  const std::string cfg = write_config(dir, "mesh");
  const Blocks whole({0, 11}, false);
  const Blocks five({0, 2, 5, 6, 9, 11}, true);
  const auto none = [](int, std::vector<tessera_mesh_domain>&) {};
  const Run ref = run_on(1, cfg, whole, false, none);
  INFO(ref.error);
  REQUIRE(ref.status == TESSERA_OK);
  bool ok = true;
  for (int n : sizes_up_to_world())
    for (const bool skip1 : {false, true}) {
      if (skip1 && n < 3) continue;
      const Run r = run_on(n, cfg, five, skip1, none);
      INFO(n << " ranks" << (skip1 ? ", none on rank 1" : "") << ": " << r.error);
      REQUIRE(r.status == TESSERA_OK);
      if (world_rank() == 0) {
        CHECK(same(ref.image, r.image));
        ok = ok && same(ref.image, r.image);
      }
    }
  REQUIRE(all_ranks(ok));
}

TEST_CASE("mesh domains: a bad element or a field published differently fails on every rank", "[mpi][mesh][errors]") {
  SharedTempDir dir;
  const std::string cfg = write_config(dir, "bad");
  Blocks five({0, 2, 5, 6, 9, 11}, true);
  const int n = std::min(world_size(), 3);
  // The last rank's first domain gets a NaN coordinate
  const Run nan = run_on(n, cfg, five, false, [&](int r, std::vector<tessera_mesh_domain>& mine) {
    if (r == n - 1 && !mine.empty()) {
      static std::vector<double> x;
      x.assign(static_cast<const double*>(mine[0].coords.x),
               static_cast<const double*>(mine[0].coords.x) + mine[0].coords.count);
      x[7] = std::nan("");
      mine[0].coords.x = x.data();
    }
  });
  CHECK(nan.status == TESSERA_ERROR_DATA);
  if (world_rank() == 0) CHECK_THAT(nan.error, Catch::Matchers::Contains("non-finite coordinate"));
  if (n > 1) {
    // The last rank publishes float32 values where the others publish float64
    std::vector<float> values;
    std::vector<tessera_field> f32;
    const Run dtype = run_on(n, cfg, five, false, [&](int r, std::vector<tessera_mesh_domain>& mine) {
      if (r != n - 1) return;
      f32.resize(mine.size());
      values.clear();
      std::size_t total = 0;
      for (const auto& d : mine) total += static_cast<std::size_t>(d.fields[0].dims[0]);
      values.reserve(total);
      for (std::size_t k = 0; k < mine.size(); ++k) {
        const std::size_t at = values.size();
        const auto* src = static_cast<const double*>(mine[k].fields[0].data);
        for (std::int64_t e = 0; e < mine[k].fields[0].dims[0]; ++e) values.push_back(static_cast<float>(src[e]));
        f32[k] = mine[k].fields[0];
        f32[k].data = values.data() + at;
        f32[k].dtype = TESSERA_FLOAT32;
        f32[k].byte_strides[0] = 4;
        mine[k].fields = &f32[k];
      }
    });
    CHECK(dtype.status == TESSERA_ERROR_DATA);
    if (world_rank() == 0) CHECK_THAT(dtype.error, Catch::Matchers::Contains("ranks publish field 'f' as"));
  }
}

TEST_CASE("mesh domains: the lookup structure is reused across calls only when every rank holds the same geometry",
          "[mpi][mesh][reuse]") {
  SharedTempDir dir;
  const std::string cfg = write_config(dir, "reuse");
  const std::string fresh_cfg = write_config(dir, "reuse_fresh");  // its own output directory
  Blocks five({0, 2, 5, 6, 9, 11}, true);
  const int n = std::min(world_size(), 3);
  FirstRanks sub(n);
  bool ok = true;
  if (sub.member()) {
    int r = 0;
    MPI_Comm_rank(sub.comm(), &r);
    tessera::insitu::Adapter ad;
    ad.set_quiet(true);
    REQUIRE(ad.open(cfg, MPI_Comm_c2f(sub.comm())) == TESSERA_OK);
    std::vector<tessera_mesh_domain> mine;
    for (std::size_t d = 0; d < five.domains.size(); ++d)
      if (static_cast<int>(d % static_cast<std::size_t>(n)) == r) mine.push_back(five.domains[d]);
    const auto reused = [&] { return !ad.last_results().empty() && ad.last_results()[0].mesh_layout_reused; };
    // Several ranks: only the values move while every rank holds the last exchange's geometry
    const auto values_only = [&] { return !ad.last_results().empty() && ad.last_results()[0].mesh_values_only; };
    // and over the kept structure each rank summarises a share of the values
    const auto shared = [&] { return !ad.last_results().empty() && ad.last_results()[0].mesh_summary_shared; };
    ok = ok && ad.execute_mesh_domains(1, 0.0, mine) == TESSERA_OK && !reused() && !values_only() && !shared();
    const std::uint64_t all_bytes = ad.last_results().empty() ? 0 : ad.last_results()[0].mesh_exchange_bytes;
    ok = ok && (n == 1 ? all_bytes == 0 : all_bytes > 0);
    // Only rank 0 promises; the others' geometry hashes as the one the structure was built
    // over: reused on every rank
    if (r == 0) ad.mesh_unchanged();
    ok = ok && ad.execute_mesh_domains(2, 0.1, mine) == TESSERA_OK && reused() && values_only() == (n > 1) &&
         shared() == (n > 1);
    // the values alone: for these float64 hexes and curvilinear blocks, well under a quarter
    const std::uint64_t value_bytes = ad.last_results().empty() ? 0 : ad.last_results()[0].mesh_exchange_bytes;
    ok = ok && (n == 1 ? value_bytes == 0 : value_bytes > 0 && 4 * value_bytes < all_bytes);
    // Rank 0 promises, rank 1 moved a vertex: built again on every rank, everything exchanged
    if (r == 0) ad.mesh_unchanged();
    if (r == 1) five.blocks[1].x[3] += 1e-3;  // domain 1 is rank 1's
    ok = ok && ad.execute_mesh_domains(3, 0.2, mine) == TESSERA_OK && (n == 1 ? reused() : !reused()) &&
         !values_only() && !shared();
    // Every rank promises, new values: reused on every rank, the values alone exchanged, and
    // the image a fresh adapter's (which exchanges everything) bit for bit
    for (MeshBlock& b : five.blocks)
      for (double& v : b.vertex_values) v = 1.0 - v;
    ad.mesh_unchanged();
    ok = ok && ad.execute_mesh_domains(4, 0.3, mine) == TESSERA_OK && reused() && values_only() == (n > 1) &&
         shared() == (n > 1);
    const tessera::Image* kept = ad.last_image("view");
    tessera::insitu::Adapter fresh;
    fresh.set_quiet(true);
    ok = ok && fresh.open(fresh_cfg, MPI_Comm_c2f(sub.comm())) == TESSERA_OK;
    ok = ok && fresh.execute_mesh_domains(4, 0.3, mine) == TESSERA_OK && !fresh.last_results().empty() &&
         !fresh.last_results()[0].mesh_values_only && !fresh.last_results()[0].mesh_summary_shared;
    if (r == 0) {
      INFO("step 4: " << ad.last_error() << " / " << fresh.last_error());
      ok = ok && kept && fresh.last_image("view") && same(*kept, *fresh.last_image("view"));
    }
  }
  CHECK(all_ranks(ok));
}
