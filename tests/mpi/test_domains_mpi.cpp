// tessera_execute_domains over MPI: the same global field cut into 1 or 7 uneven domains
// (own arrays and layouts, NaN ghosts) spread over 1, 2, 3 (and 4) ranks, a rank holding
// none, and every rank on its own pretend node, renders bit-identically to one rank's
// tessera_execute of the whole field, in replicated and distributed mode, with single and
// multiple scattering; ranks that disagree on the mesh, or whose domains do not fit together,
// all get TESSERA_ERROR_DATA and none hangs. For vertex and cell data, on uniform and
// stretched (rectilinear) axes.
#include "axis_pieces.h"
#include "domain_cuts.h"
#include "mpi_test_support.h"

#include <tessera/adapter.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

using namespace tessera_mpi_test;
using tessera_test::CutBox;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

const Dims kG{29, 26, 24};

std::string config_text(const std::string& output_dir, const std::string& distribution, const std::string& scattering) {
  return "tessera:\n  output_dir: " + output_dir + "\n  distribution: " + distribution +
         "\n  threads: 1\n"
         "renders:\n"
         "  - name: view\n"
         "    field: density\n"
         "    image: {width: 48, height: 36, spp: 3}\n"
         "    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: 3.2}}, look_at: center, "
         "up: [0, 0, 1], fov: 30}\n"
         "    transfer_function: {range: auto, density_scale: 30, opacity: [[0, 0], [0.2, 0.1], [1, 1]], "
         "diffuse: viridis, emission: [[0, [0, 0, 0]], [0.7, [0, 0, 0]], [1, [1, 0.4, 0.1]]]}\n"
         "    lights: [{type: rect, position: [2, -1, 3], target: center, size: {relative: 1}, intensity: 8}]\n"
         "    background: {type: constant, color: [0.1, 0.1, 0.15]}\n"
         "    integrator: {scattering: " +
         scattering +
         ", max_bounces: 6, tile: 8, seed: 5}\n"
         "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
}

/// Which domains a rank of n holds.
enum class Deal { All, RoundRobin, NoneOnRank1 };

std::vector<tessera_domain> dealt(const HeldDomains& held, Deal deal, int rank, int n) {
  if (deal == Deal::All) return rank == 0 ? held.of_rank(0, 1) : std::vector<tessera_domain>{};
  if (deal == Deal::RoundRobin || n < 3) return held.of_rank(rank, n);
  // Rank 1 holds nothing; the others share the domains round robin
  if (rank == 1) return {};
  const int slot = rank == 0 ? 0 : rank - 1;
  return held.of_rank(slot, n - 1);
}

/// Per-rank changes before the call (rank, mesh, domains); may replace the call by
/// tessera_execute of a one-block field (returns true).
using Edit = std::function<void(int, tessera_mesh&, std::vector<tessera_domain>&)>;

struct Run {
  tessera_status status = TESSERA_OK;   ///< the same on every member (-1 if they differed)
  std::string error;                    ///< rank 0's
  std::optional<tessera::Image> image;  ///< rank 0's
};

const tessera_test::TestMesh& uniform_vertex_mesh() {
  static const tessera_test::TestMesh m(kG, TESSERA_VERTEX, tessera_test::Axes::Uniform);
  return m;
}

/// Step 4 on the first n ranks with `held` dealt out on `base` (the mesh every rank passes
/// before `edit`); `whole_execute`: rank 0 of one rank publishes domain 0 through
/// tessera_execute instead (the reference; a uniform vertex mesh).
Run run_on(int n, const std::string& cfg, const HeldDomains& held, Deal deal, const Edit& edit = {},
           const tessera_mesh& base = uniform_vertex_mesh().mesh(), bool whole_execute = false, int execute_rank = -1) {
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
      std::vector<tessera_domain> domains = dealt(held, deal, r, n);
      if (edit) edit(r, mesh, domains);
      if (whole_execute || r == execute_rank) {
        // tessera_execute of the first domain (the whole field when held has one box)
        const tessera_domain d = held.of_rank(0, 1)[0];
        tessera_grid g{};
        for (int a = 0; a < 3; ++a) {
          g.origin[a] = mesh.origin[a];
          g.spacing[a] = mesh.spacing[a];
          g.global_dims[a] = mesh.global_dims[a];
          g.offset[a] = d.offset[a];
        }
        status = ad.execute(4, 0.25, g, std::span<const tessera_field>(d.fields, 1));
      } else {
        status = ad.execute_domains(4, 0.25, mesh, domains);
      }
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

std::string write_config(const SharedTempDir& dir, const std::string& name, const std::string& distribution,
                         const std::string& scattering) {
  const std::string out = dir.file(name);
  if (world_rank() == 0) std::ofstream(out + ".yaml") << config_text(out, distribution, scattering);
  MPI_Barrier(MPI_COMM_WORLD);
  return out + ".yaml";
}

}  // namespace

TEST_CASE("domains: 1 vs 7 uneven domains over 1, 2, 3 ranks give tessera_execute's image bit for bit, both modes",
          "[mpi][domains][determinism]") {
  SharedTempDir dir;
  const HeldDomains whole(kG, {CutBox{{0, 0, 0}, kG}});
  const HeldDomains seven(kG, tessera_test::seven_cuts(kG), 2);
  using tessera_test::Axes;
  for (const tessera_association assoc : {TESSERA_VERTEX, TESSERA_CELL}) {
    for (const Axes axes : {Axes::Uniform, Axes::StretchedY, Axes::StretchedAll}) {
      const tessera_test::TestMesh mesh(kG, assoc, axes);
      const tessera_mesh& m = mesh.mesh();
      const std::string what =
          std::string(assoc == TESSERA_CELL ? "cell" : "vertex") + " data, " + tessera_test::axes_name(axes);
      for (const std::string scattering : {"single", "multiple"}) {
        for (const std::string mode : {"replicated", "distributed"}) {
          const std::string cfg = write_config(dir, mode + "_" + scattering, mode, scattering);
          // Uniform vertex data: one rank's tessera_execute of the whole field; else one domain
          const bool plain = assoc == TESSERA_VERTEX && axes == Axes::Uniform;
          const Run ref = run_on(1, cfg, whole, Deal::All, {}, m, plain);
          REQUIRE(ref.status == TESSERA_OK);
          bool ok = true;
          const auto compare = [&](const Run& r, const std::string& how) {
            INFO(what << ", " << mode << ", " << scattering << ": " << how << ": " << r.error);
            REQUIRE(r.status == TESSERA_OK);
            if (world_rank() == 0) {
              const bool same = same_image(*ref.image, *r.image);
              CHECK(same);
              ok = ok && same;
            }
          };
          if (plain) compare(run_on(1, cfg, whole, Deal::All, {}, m), "1 domain, 1 rank");
          for (int n : sizes_up_to_world()) {
            // The other meshes (to keep the suite's time in check): 1, 2, 3 and all ranks, and
            // the rank without domains on 3 or more
            if (!plain && n > 3 && n < world_size()) continue;
            compare(run_on(n, cfg, seven, Deal::RoundRobin, {}, m), "7 domains, " + std::to_string(n) + " ranks");
            if (plain) compare(run_on(n, cfg, whole, Deal::All, {}, m), "1 domain on rank 0 of " + std::to_string(n));
            if (n >= 3)
              compare(run_on(n, cfg, seven, Deal::NoneOnRank1, {}, m),
                      "7 domains, none on rank 1 of " + std::to_string(n));
          }
          // Every rank on a pretend node of its own: the replica's inter-node exchange
          if (world_size() > 1) {
            setenv("TESSERA_MPI_RANKS_PER_NODE", "1", 1);
            compare(run_on(world_size(), cfg, seven, Deal::RoundRobin, {}, m), "7 domains, one rank per node");
            unsetenv("TESSERA_MPI_RANKS_PER_NODE");
          }
          // Another mesh renders another image: the stretch and the association reach the renderer
          if (!plain) {
            const Run other = run_on(1, cfg, whole, Deal::All, {}, uniform_vertex_mesh().mesh(), true);
            if (world_rank() == 0) CHECK_FALSE(same_image(*ref.image, *other.image));
          }
          REQUIRE(all_ranks(ok));
        }
      }
    }
  }
}

TEST_CASE("domains: ranks that disagree on the mesh, or whose domains do not fit, all fail with TESSERA_ERROR_DATA",
          "[mpi][domains][errors]") {
  if (world_size() < 2) return;  // needs two ranks
  SharedTempDir dir;
  const int n = world_size();
  const HeldDomains seven(kG, tessera_test::seven_cuts(kG), 1);
  static std::vector<double> coords;
  coords.resize(static_cast<std::size_t>(kG[1]));
  for (std::size_t q = 0; q < coords.size(); ++q) coords[q] = -0.5 + static_cast<double>(q) / (kG[1] - 1.0);
  static tessera_field f64;  // rank 1's field with bad ghosts
  struct Case {
    const char* name;
    Edit edit;
    const char* words;
    int execute_rank = -1;
  };
  const std::vector<Case> cases = {
      {"rank 1's origin differs",
       [](int r, tessera_mesh& m, auto&) {
         if (r == 1) m.origin[2] += 1e-9;
       },
       "ranks disagree on the mesh at step 4: rank 1 has origin [-0.5, -0.5, -0.499999999], rank 0 has "
       "[-0.5, -0.5, -0.5] (origin[2] (k) differs)"},
      {"rank 1's axis j is rectilinear (the same values)",
       [](int r, tessera_mesh& m, auto&) {
         if (r == 1) m.coords[1] = coords.data();
       },
       "ranks disagree on the mesh at step 4: axis j is rectilinear (coords[1] (j) set) on rank 1 but uniform "
       "(spacing 0.04) on rank 0"},
      {"rank 1's coordinates differ at one index",
       [](int r, tessera_mesh& m, auto&) {
         static std::vector<double> other;
         other = coords;
         other[17] += 1e-6;
         m.coords[1] = r == 1 ? other.data() : coords.data();
       },
       "ranks disagree on the mesh at step 4: coords[1] (j)[17] is 0.18000100000000005 on rank 1, 0.18000000000000005 "
       "on rank 0"},
      {"rank 1's refinement ratio differs",
       [](int r, tessera_mesh& m, auto&) {
         static const int two[1] = {2}, four[1] = {4};
         m.nlevels = 2;
         m.refinement = r == 1 ? four : two;
       },
       "ranks disagree on the mesh at step 4: rank 1's mesh has refinement[0] = 4 (level 0 -> 1), rank 0's 2"},
      {"rank 1's mesh is cell data",
       [](int r, tessera_mesh& m, auto&) {
         if (r == 1) m.association = TESSERA_CELL;
       },
       "ranks disagree on the mesh at step 4: rank 1's mesh has cell data (TESSERA_CELL), rank 0's vertex data "
       "(TESSERA_VERTEX)"},
      {"rank 1's first domain overlaps another",
       [](int r, tessera_mesh&, std::vector<tessera_domain>& d) {
         if (r == 1) d[0].offset[1] -= 1;
       },
       "overlap"},
      {"rank 1 leaves out its domains: a gap",
       [](int r, tessera_mesh&, std::vector<tessera_domain>& d) {
         if (r == 1) d.clear();
       },
       "cover"},
      {"rank 1's ghosts are larger than its array",
       [](int r, tessera_mesh&, std::vector<tessera_domain>& d) {
         if (r != 1) return;
         f64 = d[0].fields[0];
         f64.ghosts_lo[1] = 500;
         d[0].fields = &f64;
       },
       "rank 1"},
      {"rank 1 publishes uint8",
       [](int r, tessera_mesh&, std::vector<tessera_domain>& d) {
         if (r != 1) return;
         static std::vector<tessera_field> bytes;
         bytes.clear();
         for (const tessera_domain& x : d) bytes.push_back(x.fields[0]);
         for (std::size_t q = 0; q < d.size(); ++q) {
           bytes[q].dtype = TESSERA_UINT8;  // (never read: the ranks' field lists are compared first)
           d[q].fields = &bytes[q];
         }
       },
       "ranks disagree on the published fields at step 4: field 'density' is uint8 on rank 1, float32 on rank 0"},
      {"rank 1 publishes a field the others do not (the same error as between the domains of one rank)",
       [](int r, tessera_mesh&, std::vector<tessera_domain>& d) {
         if (r != 1) return;
         static std::vector<std::vector<tessera_field>> lists;
         lists.assign(d.size(), {});
         for (std::size_t q = 0; q < d.size(); ++q) {
           lists[q] = {d[q].fields[0], d[q].fields[0]};
           lists[q][1].name = "pressure";
           lists[q][1].dtype = TESSERA_FLOAT64;  // (never read)
           d[q].fields = lists[q].data();
           d[q].nfields = 2;
         }
       },
       "ranks disagree on the published fields at step 4: field 'pressure' (float64) is published on rank 1 but "
       "not on rank 0 (every domain of every rank must publish the same fields"},
      {"rank 1 says its field is cell data",
       [](int r, tessera_mesh&, std::vector<tessera_domain>& d) {
         static const tessera_association cell[1] = {TESSERA_CELL};
         if (r == 1)
           for (tessera_domain& x : d) x.associations = cell;
       },
       "ranks disagree on the published fields at step 4: field 'density' is cell data (TESSERA_CELL) on rank 1, "
       "vertex data (TESSERA_VERTEX) on rank 0"},
      {"rank 1's nlevels is 2",
       [](int r, tessera_mesh& m, auto&) {
         static const int ratio2[1] = {2};
         if (r != 1) return;
         m.nlevels = 2;
         m.refinement = ratio2;
       },
       "ranks disagree on the mesh at step 4: rank 1's mesh has nlevels = 2, rank 0's 1"},
      {"rank 1 calls tessera_execute", {}, "tessera_execute", 1},
  };
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.name) {
      const std::string cfg = write_config(dir, "bad", "auto", "single");
      const Run r =
          run_on(n, cfg, seven, Deal::RoundRobin, c.edit, uniform_vertex_mesh().mesh(), false, c.execute_rank);
      INFO(r.error);
      CHECK(r.status == TESSERA_ERROR_DATA);
      if (world_rank() == 0) CHECK_THAT(r.error, Catch::Contains(c.words));
      // The same communicator renders afterwards: nobody hangs
      CHECK(run_on(n, cfg, seven, Deal::RoundRobin).status == TESSERA_OK);
    }
  }
}

TEST_CASE(
    "domains: ten thousand one-vertex domains per rank render in distributed mode as in replicated, in bounded time",
    "[mpi][domains][distributed]") {
  // 25x20x40 one-vertex domains dealt round robin over 2 ranks (every brick spans both): the
  // summaries, the tiling checks, the in-place table and the brick service each cost per
  // domain, not domains x macrocells
  if (world_size() < 2) return;
  const Dims g{25, 20, 40};
  std::vector<CutBox> boxes;
  for (std::int64_t k = 0; k < g[2]; ++k)
    for (std::int64_t j = 0; j < g[1]; ++j)
      for (std::int64_t i = 0; i < g[0]; ++i) boxes.push_back(CutBox{{i, j, k}, {1, 1, 1}});
  const HeldDomains tiny(g, boxes, 0);
  SharedTempDir dir;
  std::optional<tessera::Image> images[2];
  int m = 0;
  for (const std::string mode : {"replicated", "distributed"}) {
    const std::string cfg = write_config(dir, "tiny_" + mode, mode, "single");
    const auto t0 = std::chrono::steady_clock::now();
    const Run r = run_on(2, cfg, tiny, Deal::RoundRobin, {}, tessera_test::unit_mesh(g, TESSERA_VERTEX));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    INFO(mode << ": " << r.error << " (" << seconds << " s)");
    REQUIRE(r.status == TESSERA_OK);  // (the time is reported, not asserted: CTest's timeout bounds it)
    images[m++] = r.image;
  }
  if (world_rank() == 0) CHECK(same_image(*images[0], *images[1]));
}

TEST_CASE("domains: cell data on a vertex mesh (per-field association), a rank without domains included, renders "
          "as on a cell mesh",
          "[mpi][domains][association]") {
  SharedTempDir dir;
  const int n = world_size();
  const Dims cells{kG[0] - 1, kG[1] - 1, kG[2] - 1};
  const HeldDomains seven(cells, tessera_test::seven_cuts(cells), 1);
  const std::string cfg = write_config(dir, "assoc", "auto", "single");
  const Run ref = run_on(1, cfg, seven, Deal::All, {}, tessera_test::unit_mesh(cells, TESSERA_CELL));
  const Edit as_cells = [](int, tessera_mesh&, std::vector<tessera_domain>& d) {
    static const tessera_association cell[1] = {TESSERA_CELL};
    for (tessera_domain& x : d) x.associations = cell;
  };
  for (const Deal deal : {Deal::RoundRobin, Deal::NoneOnRank1}) {
    const Run r = run_on(n, cfg, seven, deal, as_cells, uniform_vertex_mesh().mesh());
    INFO(r.error);
    CHECK(r.status == TESSERA_OK);
    if (world_rank() == 0 && r.status == TESSERA_OK && ref.status == TESSERA_OK)
      CHECK(same_image(*ref.image, *r.image));
  }
}

TEST_CASE("domains: per-domain coordinates dealt over the ranks (a rank without domains included) assemble into the "
          "axis and render as the whole axis",
          "[mpi][domains][pieces]") {
  SharedTempDir dir;
  const int n = world_size();
  static const tessera_test::TestMesh stretched(kG, TESSERA_VERTEX, tessera_test::Axes::StretchedY);
  const HeldDomains seven(kG, tessera_test::seven_cuts(kG), 1);
  const std::string cfg = write_config(dir, "pieces", "auto", "single");
  const Run ref = run_on(1, cfg, seven, Deal::All, {}, stretched.mesh());
  const Edit in_pieces = [](int, tessera_mesh& m, std::vector<tessera_domain>& d) {
    static tessera_test::AxisPieces pieces;
    const std::vector<double> axis(stretched.mesh().coords[1], stretched.mesh().coords[1] + kG[1]);
    pieces.give(d, 1, axis, 1);
    m.coords[1] = nullptr;
    m.axes_from_domains = 2;
  };
  for (const Deal deal : {Deal::RoundRobin, Deal::NoneOnRank1}) {
    const Run r = run_on(n, cfg, seven, deal, in_pieces, stretched.mesh());
    INFO(r.error);
    CHECK(r.status == TESSERA_OK);
    if (world_rank() == 0 && r.status == TESSERA_OK && ref.status == TESSERA_OK)
      CHECK(same_image(*ref.image, *r.image));
  }
  // Rank 1's piece disagrees with a neighbour's: every rank fails, naming both
  if (n >= 2) {
    const Edit differ = [&](int r, tessera_mesh& m, std::vector<tessera_domain>& d) {
      in_pieces(r, m, d);
      static std::vector<double> changed;
      if (r != 1 || d.empty()) return;
      changed.assign(d[0].coords[1], d[0].coords[1] + d[0].coords_count[1]);
      for (double& v : changed) v += 1e-3;
      d[0].coords[1] = changed.data();
    };
    const Run r = run_on(n, cfg, seven, Deal::RoundRobin, differ, stretched.mesh());
    INFO(r.error);
    CHECK(r.status == TESSERA_ERROR_DATA);
    if (world_rank() == 0) CHECK_THAT(r.error, Catch::Contains("rank 1 domain") && Catch::Contains("bit for bit"));
  }
}
