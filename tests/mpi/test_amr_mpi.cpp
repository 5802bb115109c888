// Refinement levels over MPI (tessera_execute_domains): the same patches of
// a 2-level (ratio 2, vertex data) and a 3-level (ratios 2, 4, cell data) hierarchy dealt
// over 1, 2 and 3 ranks in different assignments (round robin, reversed, all on the last
// rank, every rank on its own pretend node) give the one-process image of the hierarchy cut
// in one patch per level, bit for bit, in replicated and in distributed mode (other ranks'
// patches paged through the brick cache, a small cache too); ranks that disagree on nlevels or ratios, or whose patches do not fit
// together, get TESSERA_ERROR_DATA on every rank, and level tables over memory_limit_mb the
// limit's message on every rank; the communicator renders afterwards.
#include "amr_patches.h"
#include "mpi_test_support.h"

#include <tessera/adapter.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

using namespace tessera_mpi_test;
using tessera_test::AmrMeshSpec;
using tessera_test::HeldPatches;
using tessera_test::Hierarchy;

namespace {

std::string config_text(const std::string& output_dir, const std::string& distribution, const std::string& global) {
  return "tessera:\n  output_dir: " + output_dir + "\n  distribution: " + distribution + "\n  threads: 1\n" + global +
         "renders:\n"
         "  - name: view\n"
         "    field: density\n"
         "    image: {width: 40, height: 32, spp: 3}\n"
         "    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: 3.2}}, look_at: center, "
         "up: [0, 0, 1], fov: 30}\n"
         "    transfer_function: {range: auto, density_scale: 30, opacity: [[0, 0], [0.2, 0.1], [1, 1]], "
         "diffuse: viridis}\n"
         "    lights: [{type: rect, position: [2, -1, 3], target: center, size: {relative: 1}, intensity: 8}]\n"
         "    background: {type: constant, color: [0.1, 0.1, 0.15]}\n"
         "    integrator: {scattering: multiple, max_bounces: 6, tile: 8, seed: 5}\n"
         "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
}

std::string write_config(const SharedTempDir& dir, const std::string& name, const std::string& distribution,
                         const std::string& global = "") {
  const std::string out = dir.file(name);
  if (world_rank() == 0) std::ofstream(out + ".yaml") << config_text(out, distribution, global);
  MPI_Barrier(MPI_COMM_WORLD);
  return out + ".yaml";
}

/// Which rank of n holds patch p (of `count`).
using Owner = std::function<int(std::size_t p, int n)>;

/// Per-rank changes of the mesh and the descriptors before the call.
using Edit = std::function<void(int, tessera_mesh&, std::vector<tessera_domain>&)>;

struct Run {
  tessera_status status = TESSERA_OK;   ///< the same on every member (-1 if they differed)
  std::string error;                    ///< rank 0's
  std::optional<tessera::Image> image;  ///< rank 0's
};

Run run_on(int n, const std::string& cfg, const tessera_mesh& base, const HeldPatches& held, const Owner& owner,
           const Edit& edit = {}) {
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
      tessera_mesh mesh = base;
      std::vector<tessera_domain> domains = held.of_rank(r, [&](std::size_t p) { return owner(p, n); });
      if (edit) edit(r, mesh, domains);
      status = ad.execute_domains(4, 0.25, mesh, domains);
      if (r == 0) {
        run.error = ad.last_error();
        if (const tessera::Image* img = ad.last_image("view")) run.image = *img;
      }
    }
  }
  run.status = static_cast<tessera_status>(sub.agreed_status(status));
  return run;
}

bool same_image(const tessera::Image& a, const tessera::Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

const Owner kRoundRobin = [](std::size_t p, int n) { return static_cast<int>(p % static_cast<std::size_t>(n)); };
const Owner kReversed = [](std::size_t p, int n) { return n - 1 - static_cast<int>(p % static_cast<std::size_t>(n)); };
const Owner kLastRank = [](std::size_t, int n) { return n - 1; };
const Owner kRankZero = [](std::size_t, int) { return 0; };

}  // namespace

TEST_CASE("levels: the same patches over 1, 2, 3 ranks in any assignment give the one-process image bit for bit",
          "[mpi][amr][determinism]") {
  SharedTempDir dir;
  const std::string cfg = write_config(dir, "replicated", "replicated");
  for (const auto& [nlevels, assoc] : {std::pair{2, TESSERA_VERTEX}, std::pair{3, TESSERA_CELL}}) {
    const Hierarchy h = tessera_test::hierarchy(nlevels, assoc);
    const HeldPatches one(h.spec, h.one, tessera_test::blobs, 1);
    const HeldPatches many(h.spec, h.many, tessera_test::blobs, 2);
    const tessera_mesh mesh = h.spec.mesh();
    const Run ref = run_on(1, cfg, mesh, one, kRankZero);
    INFO(nlevels << " levels: " << ref.error);
    REQUIRE(ref.status == TESSERA_OK);
    bool ok = true;
    const auto compare = [&](const Run& r, const std::string& how) {
      INFO(nlevels << " levels, " << how << ": " << r.error);
      REQUIRE(r.status == TESSERA_OK);
      if (world_rank() == 0) {
        const bool same = same_image(*ref.image, *r.image);
        CHECK(same);
        ok = ok && same;
      }
    };
    for (int n = 1; n <= std::min(3, world_size()); ++n) {
      const std::string on = " over " + std::to_string(n) + " ranks";
      compare(run_on(n, cfg, mesh, many, kRoundRobin), "round robin" + on);
      compare(run_on(n, cfg, mesh, many, kReversed), "reversed" + on);
      compare(run_on(n, cfg, mesh, many, kLastRank), "all on the last rank" + on);
      compare(run_on(n, cfg, mesh, one, kReversed), "a patch per level" + on);
    }
    // Every rank on a pretend node of its own: the replica's inter-node exchange
    if (world_size() > 1) {
      setenv("TESSERA_MPI_RANKS_PER_NODE", "1", 1);
      compare(run_on(world_size(), cfg, mesh, many, kRoundRobin), "one rank per node");
      unsetenv("TESSERA_MPI_RANKS_PER_NODE");
    }
    REQUIRE(all_ranks(ok));
  }
}

TEST_CASE("levels: distributed mode (other ranks' patches paged) gives the one-process image bit for bit",
          "[mpi][amr][determinism][distributed]") {
  SharedTempDir dir;
  const std::string replicated = write_config(dir, "replicated", "replicated");
  const std::string distributed = write_config(dir, "distributed", "distributed");
  // A cache of a few bricks: evictions and refetches on the way
  const std::string small = write_config(dir, "small", "distributed", "  brick_cache: 0.05\n");
  for (const auto& [nlevels, assoc] : {std::pair{2, TESSERA_VERTEX}, std::pair{3, TESSERA_CELL}}) {
    const Hierarchy h = tessera_test::hierarchy(nlevels, assoc);
    const HeldPatches one(h.spec, h.one, tessera_test::blobs, 1);
    const HeldPatches many(h.spec, h.many, tessera_test::blobs, 2);
    const tessera_mesh mesh = h.spec.mesh();
    const Run ref = run_on(1, replicated, mesh, one, kRankZero);
    INFO(nlevels << " levels: " << ref.error);
    REQUIRE(ref.status == TESSERA_OK);
    bool ok = true;
    // At this run's rank count only (the np2 and np3 entries cover both): distributed mode
    // polls while it serves, which oversubscribed ranks pay for dearly
    const int n = world_size();
    if (n < 2) return;
    for (const auto& [cfg, how] : {std::pair{distributed, "distributed"}, std::pair{small, "small cache"}})
      for (const auto& [owner, who] : {std::pair{kRoundRobin, "round robin"}, std::pair{kReversed, "reversed"},
                                       std::pair{kLastRank, "all on the last rank"}}) {
        // (3 oversubscribed ranks wait seconds per render on each other's brick service: one
        // assignment there, every one at 2 ranks)
        if ((cfg == small && n > 2) || ((cfg == small || n > 2) && who != std::string("round robin"))) continue;
        const Run r = run_on(n, cfg, mesh, many, owner);
        INFO(nlevels << " levels, " << how << ", " << who << " over " << n << " ranks: " << r.error);
        REQUIRE(r.status == TESSERA_OK);
        if (world_rank() == 0) {
          const bool same = same_image(*ref.image, *r.image);
          CHECK(same);
          ok = ok && same;
        }
      }
    REQUIRE(all_ranks(ok));
  }
}

TEST_CASE("levels: ranks that disagree on the levels, or whose patches do not fit, all fail with TESSERA_ERROR_DATA",
          "[mpi][amr][errors]") {
  if (world_size() < 2) return;  // needs two ranks
  SharedTempDir dir;
  const std::string cfg = write_config(dir, "bad", "replicated");
  const Hierarchy h = tessera_test::hierarchy(3, TESSERA_VERTEX);
  const HeldPatches many(h.spec, h.many, tessera_test::blobs, 1);
  const tessera_mesh mesh = h.spec.mesh();
  const int n = world_size();
  static const int other_ratios[2] = {2, 2};
  struct Case {
    const char* name;
    Edit edit;
    const char* words;
  };
  const std::vector<Case> cases = {
      {"rank 1's nlevels is 2",
       [](int r, tessera_mesh& m, std::vector<tessera_domain>& d) {
         if (r != 1) return;
         m.nlevels = 2;
         std::erase_if(d, [](const tessera_domain& x) { return x.level == 2; });
       },
       "ranks disagree on the mesh at step 4: rank 1's mesh has nlevels = 2, rank 0's 3"},
      {"rank 1's ratios are 2, 2",
       [](int r, tessera_mesh& m, auto&) {
         if (r == 1) m.refinement = other_ratios;
       },
       "ranks disagree on the mesh at step 4: rank 1's mesh has refinement[1] = 2 (level 1 -> 2), rank 0's 4"},
      {"rank 1 passes a level-1 patch twice",
       [](int r, tessera_mesh&, std::vector<tessera_domain>& d) {
         if (r != 1) return;
         for (const tessera_domain& x : d)
           if (x.level == 1) {
             d.push_back(x);  // the same box twice: they overlap
             break;
           }
       },
       "rank 1 domain"},
      {"rank 1 moves a level-2 patch out of level 1",
       [](int r, tessera_mesh&, std::vector<tessera_domain>& d) {
         if (r != 1) return;
         for (tessera_domain& x : d)
           if (x.level == 2) {
             x.offset[0] = x.offset[1] = x.offset[2] = 0;  // level 1 starts at level-0 cell 3
             break;
           }
       },
       "is not inside the region level 1 covers"},
  };
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.name) {
      const Run r = run_on(n, cfg, mesh, many, kRoundRobin, c.edit);
      INFO(r.error);
      CHECK(r.status == TESSERA_ERROR_DATA);
      if (world_rank() == 0) CHECK_THAT(r.error, Catch::Contains(c.words));
      // The same communicator renders afterwards: nobody hangs
      CHECK(run_on(n, cfg, mesh, many, kRoundRobin).status == TESSERA_OK);
    }
  }
}

TEST_CASE("levels: level tables over tessera.memory_limit_mb fail with the limit on every rank, nothing hangs",
          "[mpi][amr][limits]") {
  SharedTempDir dir;
  const std::string small = write_config(dir, "small", "replicated", "  memory_limit_mb: 4\n");
  const std::string replicated = write_config(dir, "replicated", "replicated");
  const tessera_test::DeepCorners deep;
  const HeldPatches held(deep.spec, deep.boxes, tessera_test::blobs, 1);
  const tessera_mesh mesh = deep.spec.mesh();
  const int n = world_size();
  const Run r = run_on(n, small, mesh, held, kRoundRobin);
  INFO(r.error);
  CHECK(r.status == TESSERA_ERROR_RENDER);
  if (world_rank() == 0) {
    CHECK_THAT(r.error, Catch::Contains("refinement level tables"));
    CHECK_THAT(r.error, Catch::Contains("more than tessera.memory_limit_mb = 4 MiB"));
  }
  CHECK(run_on(n, replicated, mesh, held, kRoundRobin).status == TESSERA_OK);
}
