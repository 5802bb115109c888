// The adapter over MPI through the C API (tessera.h): each rank publishes its block of one
// global field with ghost layers; the images written by rank 0 are bit-identical for 1, 2, 3
// and 4 ranks (and with every rank on its own pretend node), and a bad field on one rank
// gives every rank an error status without a hang.
#include "mpi_test_support.h"
#include "published_block.h"

#include <tessera/adapter.h>
#include <tessera/image_io.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>

using namespace tessera_mpi_test;
namespace fs = std::filesystem;

namespace {

constexpr std::array<std::int64_t, 3> kGlobal{29, 26, 24};

/// One render, far camera so that the volume fills part of the image; EXR only.
std::string config_text(const std::string& output_dir, const std::string& distribution = "auto",
                        const std::string& scattering = "multiple", int threads = 1,
                        const std::string& brick_cache = "") {
  return "tessera:\n  output_dir: " + output_dir + "\n  distribution: " + distribution +
         "\n  threads: " + std::to_string(threads) + "\n" +
         (brick_cache.empty() ? "" : "  brick_cache: " + brick_cache + "\n") +
         "renders:\n"
         "  - name: view\n"
         "    field: density\n"
         "    image: {width: 56, height: 40, spp: 3}\n"
         "    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: 3.2}}, look_at: center, "
         "up: [0, 0, 1], fov: 30}\n"
         "    transfer_function: {range: [0, 250], density_scale: 30, opacity: [[0, 0], [0.2, 0.1], [1, 1]], "
         "diffuse: viridis, emission: [[0, [0, 0, 0]], [0.7, [0, 0, 0]], [1, [1, 0.4, 0.1]]]}\n"
         "    lights: [{type: rect, position: [2, -1, 3], target: center, size: {relative: 1}, intensity: 8}]\n"
         "    background: {type: constant, color: [0.1, 0.1, 0.15]}\n"
         "    integrator: {scattering: " +
         scattering +
         ", max_bounces: 6, tile: 8, seed: 5}\n"
         "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
}

std::array<int, 3> procs_for(int n) {
  switch (n) {
    case 1: return {1, 1, 1};
    case 2: return {1, 2, 1};
    case 3: return {3, 1, 1};
    default: return {1, 2, 2};
  }
}

/// This rank's block as the simulation holds it, described in `f` and `g`.
struct Published : PublishedBlock {
  Published(const Box& box, tessera_field& f, tessera_grid& g, const std::array<std::int64_t, 3>& global = kGlobal)
      : PublishedBlock(box, global) {
    f = field;
    g = grid;
  }
};

/// Runs step 3 of the config on the first n ranks; returns the status every rank got (agreed).
tessera_status run_on(int n, const std::string& cfg, bool break_last_rank = false) {
  FirstRanks sub(n);
  int status = TESSERA_OK;
  if (sub.member()) {
    int r = 0;
    MPI_Comm_rank(sub.comm(), &r);
    tessera_field f{};
    tessera_grid g{};
    Published pub(block_of(kGlobal, procs_for(n), r), f, g);
    if (break_last_rank && r == n - 1) f.byte_strides[0] = 0;  // an invalid descriptor
    tessera_adapter* a = nullptr;
    status = tessera_open(cfg.c_str(), MPI_Comm_c2f(sub.comm()), &a);
    if (status == TESSERA_OK) status = tessera_execute(a, 3, 0.5, &g, &f, 1);
    tessera_close(a);
  }
  // The worst status over the members (every member should report the same).
  return static_cast<tessera_status>(sub.agreed_status(status));
}

bool same_image(const tessera::Image& a, const tessera::Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

}  // namespace

TEST_CASE("adapter images are bit-identical for 1, 2, 3 and 4 ranks", "[mpi][adapter][determinism]") {
  SharedTempDir dir;
  std::vector<std::string> runs;
  for (int n : sizes_up_to_world()) {
    const std::string out = dir.file("np" + std::to_string(n));
    if (world_rank() == 0) std::ofstream(out + ".yaml") << config_text(out);
    MPI_Barrier(MPI_COMM_WORLD);
    REQUIRE(run_on(n, out + ".yaml") == TESSERA_OK);
    runs.push_back(out);
  }
  // Every rank on a pretend node of its own: the inter-node assembly path.
  if (world_size() > 1) {
    const std::string out = dir.file("one_per_node");
    if (world_rank() == 0) std::ofstream(out + ".yaml") << config_text(out);
    MPI_Barrier(MPI_COMM_WORLD);
    setenv("TESSERA_MPI_RANKS_PER_NODE", "1", 1);
    const tessera_status s = run_on(world_size(), out + ".yaml");
    unsetenv("TESSERA_MPI_RANKS_PER_NODE");
    REQUIRE(s == TESSERA_OK);
    runs.push_back(out);
  }
  bool ok = true;
  if (world_rank() == 0) {
    const tessera::Image one = tessera::read_exr(runs[0] + "/view_0003.exr");
    for (std::size_t i = 1; i < runs.size(); ++i) {
      INFO(runs[i]);
      const bool same = same_image(one, tessera::read_exr(runs[i] + "/view_0003.exr"));
      CHECK(same);
      ok = ok && same;
    }
  }
  REQUIRE(all_ranks(ok));
}

TEST_CASE("a bad field on one rank gives every rank an error status", "[mpi][adapter][errors]") {
  SharedTempDir dir;
  const std::string out = dir.file("bad");
  if (world_rank() == 0) std::ofstream(out + ".yaml") << config_text(out);
  MPI_Barrier(MPI_COMM_WORLD);
  // Every rank returns the same error status (run_on gives -1 if they differed); none hangs.
  REQUIRE(run_on(world_size(), out + ".yaml", true) == TESSERA_ERROR_DATA);
  // And the same communicator renders fine afterwards.
  REQUIRE(run_on(world_size(), out + ".yaml") == TESSERA_OK);
}

TEST_CASE("an invalid communicator handle is refused at open", "[mpi][adapter][errors]") {
  SharedTempDir dir;
  const std::string out = dir.file("handle");
  if (world_rank() == 0) std::ofstream(out + ".yaml") << config_text(out);
  MPI_Barrier(MPI_COMM_WORLD);
  tessera_adapter* a = nullptr;
  CHECK(tessera_open((out + ".yaml").c_str(), 123456, &a) == TESSERA_ERROR_CONFIG);
  CHECK(a == nullptr);
  CHECK_THAT(std::string(tessera_last_error(nullptr)), Catch::Contains("123456"));
  MPI_Barrier(MPI_COMM_WORLD);
}

TEST_CASE("field_unchanged under MPI: the summary is kept only if every rank says so", "[mpi][adapter][summary]") {
  SharedTempDir dir;
  const std::string out = dir.file("unchanged");
  if (world_rank() == 0) {
    // range: auto, so that the kept summary also replaces the range reduction
    std::string text = config_text(out);
    const std::string fixed = "range: [0, 250]";
    text.replace(text.find(fixed), fixed.size(), "range: auto");
    std::ofstream(out + ".yaml") << text;
  }
  MPI_Barrier(MPI_COMM_WORLD);
  tessera_field f{};
  tessera_grid g{};
  Published pub(block_of(kGlobal, procs_for(world_size()), world_rank()), f, g);
  tessera::insitu::Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(out + ".yaml", MPI_Comm_c2f(MPI_COMM_WORLD)) == TESSERA_OK);
  const auto passes_after = [&](std::int64_t step) {
    REQUIRE(adapter.execute(step, 0.0, g, {&f, 1}) == TESSERA_OK);
    REQUIRE(adapter.last_results().size() == 1);
    return adapter.last_results()[0].field_passes;
  };

  CHECK(passes_after(3) == 1);
  std::optional<tessera::Image> first;
  if (world_rank() == 0) first = *adapter.last_image("view");

  // Every rank promises: no pass anywhere, the same image
  REQUIRE(adapter.field_unchanged("density") == TESSERA_OK);
  CHECK(passes_after(3) == 0);
  bool same = world_rank() != 0 || same_image(*first, *adapter.last_image("view"));
  CHECK(all_ranks(same));

  // Only rank 0 promises: every rank reads the field again (and none waits for another)
  if (world_rank() == 0) REQUIRE(adapter.field_unchanged("density") == TESSERA_OK);
  CHECK(passes_after(3) == (world_size() == 1 ? 0 : 1));
  same = world_rank() != 0 || same_image(*first, *adapter.last_image("view"));
  CHECK(all_ranks(same));
  adapter.close();
}

TEST_CASE("distributed mode gives the replicated mode's images bit for bit at 1, 2, 3 and 4 ranks",
          "[mpi][adapter][distributed][determinism]") {
  SharedTempDir dir;
  for (const std::string scattering : {"single", "multiple"}) {
    // The reference: one rank (always replicated: its block is the whole field)
    const std::string ref = dir.file("ref_" + scattering);
    if (world_rank() == 0) std::ofstream(ref + ".yaml") << config_text(ref, "replicated", scattering);
    MPI_Barrier(MPI_COMM_WORLD);
    REQUIRE(run_on(1, ref + ".yaml") == TESSERA_OK);
    std::vector<std::string> runs;
    // (at one rank `distributed` reads the one block in place, as replicated mode does)
    // Caches: the default, one that keeps every brick (then one 32^3 brick covers this field)
    // and 2% of the field (one slot: at this size also the one 32^3 brick)
    struct Variant {
      int threads;
      const char* cache;
    };
    for (int n : sizes_up_to_world()) {
      for (const Variant v : {Variant{1, ""}, Variant{2, ""}, Variant{1, "1"}, Variant{2, "0.02"}}) {
        const std::string out = dir.file("dist_" + scattering + "_np" + std::to_string(n) + "_t" +
                                         std::to_string(v.threads) + "_c" + v.cache);
        if (world_rank() == 0)
          std::ofstream(out + ".yaml") << config_text(out, "distributed", scattering, v.threads, v.cache);
        MPI_Barrier(MPI_COMM_WORLD);
        REQUIRE(run_on(n, out + ".yaml") == TESSERA_OK);
        runs.push_back(out);
      }
    }
    bool ok = true;
    if (world_rank() == 0) {
      const tessera::Image one = tessera::read_exr(ref + "/view_0003.exr");
      for (const std::string& run : runs) {
        INFO(run);
        const bool same = same_image(one, tessera::read_exr(run + "/view_0003.exr"));
        CHECK(same);
        ok = ok && same;
      }
    }
    REQUIRE(all_ranks(ok));
  }
}

TEST_CASE("a bad field on one rank in distributed mode gives every rank an error status",
          "[mpi][adapter][distributed][errors]") {
  SharedTempDir dir;
  const std::string out = dir.file("bad_dist");
  if (world_rank() == 0) std::ofstream(out + ".yaml") << config_text(out, "distributed");
  MPI_Barrier(MPI_COMM_WORLD);
  REQUIRE(run_on(world_size(), out + ".yaml", true) == TESSERA_ERROR_DATA);
}

TEST_CASE("a distributed render with a cache too small to be useful warns on rank 0", "[mpi][adapter][distributed]") {
  SharedTempDir dir;
  const std::string out = dir.file("tiny_cache");
  if (world_rank() == 0) std::ofstream(out + ".yaml") << config_text(out, "distributed", "single", 1, "0.02");
  MPI_Barrier(MPI_COMM_WORLD);
  tessera_field f{};
  tessera_grid g{};
  // 80 x 72 x 64 vertices: 720 bricks of 8^3; 2% of the field is 14 of them, fewer than
  // 4 x 1 thread x 27 bricks along x + y + z (a coarser cut does not fit the cap either)
  constexpr std::array<std::int64_t, 3> global{80, 72, 64};
  Published pub(block_of(global, procs_for(world_size()), world_rank()), f, g, global);
  tessera::insitu::Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(out + ".yaml", MPI_Comm_c2f(MPI_COMM_WORLD)) == TESSERA_OK);
  REQUIRE(adapter.execute(3, 0.0, g, {&f, 1}) == TESSERA_OK);
  REQUIRE(adapter.last_results().size() == 1);
  bool warned = false;
  for (const std::string& w : adapter.last_results()[0].warnings) {
    INFO("rank " << world_rank() << " warning: " << w);
    warned = warned || w.find("the brick cache holds 14 of the field's 720 bricks") != std::string::npos;
  }
  INFO("rank " << world_rank() << " of " << world_size());
  // One rank renders replicated (its block is the field): nothing to warn about
  CHECK(warned == (world_rank() == 0 && world_size() > 1));
  adapter.close();
}
