// Ranks whose fields do not fit together (boxes that overlap, leave a gap, leave the global
// grid; a dtype that differs on one rank) fail the firing call on every rank with
// TESSERA_ERROR_DATA, like the other descriptor faults, and a message that names the ranks and
// their boxes; an empty TESSERA_MPI_RANKS_PER_NODE is reported as set but empty. Run at -n 2
// and -n 3 (with the agreement tests); the last rank is the odd one out.
#include "mpi_test_support.h"

#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

using namespace tessera_mpi_test;

namespace {

constexpr std::array<std::int64_t, 3> kLayoutGlobal{12, 12, 8};

/// Kills the process (and so the MPI job) if the test has not finished in 60 s.
struct LayoutWatchdog {
  LayoutWatchdog() { alarm(60); }
  ~LayoutWatchdog() { alarm(0); }
};

std::string layout_config(const std::string& out) {
  return "tessera:\n  output_dir: " + out +
         "\n  threads: 1\nrenders:\n  - name: view\n"
         "    field: density\n"
         "    image: {width: 8, height: 8, spp: 1}\n"
         "    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: 3.2}}, look_at: center, fov: 30}\n"
         "    transfer_function: {range: [0, 250], density_scale: 10, opacity: [[0, 0], [1, 1]]}\n"
         "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
}

/// This rank's slab (along y) of the global field, float32, no ghosts.
struct Slab {
  Slab()
      : local(block_of(kLayoutGlobal, {1, world_size(), 1}, world_rank()), tessera::DType::Float32, Layout::COrder,
              blobs(kLayoutGlobal)) {
    const Box box = block_of(kLayoutGlobal, {1, world_size(), 1}, world_rank());
    const tessera::FieldView real = local.view();
    field.name = "density";
    field.dtype = TESSERA_FLOAT32;
    field.data = real.data;
    for (int a = 0; a < 3; ++a) {
      field.dims[a] = box.dims[a];
      field.byte_strides[a] = real.byte_strides[a];
      grid.spacing[a] = 1.0 / static_cast<double>(kLayoutGlobal[a] - 1);
      grid.global_dims[a] = kLayoutGlobal[a];
      grid.offset[a] = box.offset[a];
    }
  }
  LocalArray local;
  tessera_field field{};
  tessera_grid grid{};
};

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("layout faults across ranks are TESSERA_ERROR_DATA on every rank, naming ranks and boxes",
          "[mpi][layout][robustness]") {
  if (world_size() < 2) return;
  LayoutWatchdog watchdog;
  SharedTempDir dir("tessera_layout_");
  const std::string cfg = dir.file("cfg_" + std::to_string(world_rank()) + ".yaml");
  std::ofstream(cfg) << layout_config(dir.file("out"));
  MPI_Barrier(MPI_COMM_WORLD);
  const bool odd = world_rank() == world_size() - 1;
  const std::string last = "rank " + std::to_string(world_size() - 1);

  struct Case {
    const char* name;
    void (*edit)(Slab&);
    const char* says;  ///< part of the message (rank 0's view names the last rank too)
    bool local;        ///< found by the odd rank alone (at binding): others say it failed there
  };
  const Case cases[] = {
      {"overlap: the last slab starts one row early", [](Slab& s) { s.grid.offset[1] -= 1; }, "overlap", false},
      {"gap: the last slab is one row short (declared as a ghost)",
       [](Slab& s) {
         s.field.dims[1] -= 1;
         s.field.ghosts_hi[1] = 0;
       },
       "cover", false},
      {"outside: the last slab starts one row late", [](Slab& s) { s.grid.offset[1] += 1; }, "reach past global_dims",
       true},
      {"dtype: the last rank says uint16", [](Slab& s) { s.field.dtype = TESSERA_UINT16; }, "different dtypes", false},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    Slab slab;
    if (odd) c.edit(slab);
    tessera_adapter* a = nullptr;
    REQUIRE(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK);
    const tessera_status s = tessera_execute(a, 0, 0.0, &slab.grid, &slab.field, 1);
    const std::string error = tessera_last_error(a);
    INFO(error);
    const bool ok = s == TESSERA_ERROR_DATA && (has(error, c.says) || has(error, "failed on another rank")) &&
                    (c.local || world_rank() != 0 || (has(error, c.says) && has(error, last)));
    CHECK(ok);
    tessera_close(a);
    REQUIRE(all_ranks(ok));
  }
}

TEST_CASE("an empty TESSERA_MPI_RANKS_PER_NODE is reported as set but empty", "[mpi][layout][robustness]") {
  LayoutWatchdog watchdog;
  SharedTempDir dir("tessera_layout_");
  const std::string cfg = dir.file("cfg_" + std::to_string(world_rank()) + ".yaml");
  std::ofstream(cfg) << layout_config(dir.file("out"));
  MPI_Barrier(MPI_COMM_WORLD);
  const char* kKnob = "TESSERA_MPI_RANKS_PER_NODE";
  const char* saved = std::getenv(kKnob);
  const std::string restore = saved ? saved : "";
  const auto open_fails_with = [&](const std::string& says) {
    tessera_adapter* a = nullptr;
    const tessera_status s = tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a);
    const std::string error = tessera_last_error(nullptr);
    INFO(error);
    const bool ok = s == TESSERA_ERROR_CONFIG && a == nullptr && has(error, says);
    CHECK(ok);
    if (a) tessera_close(a);
    return ok;
  };
  // Empty on every rank: an error saying so (it was taken as unset)
  setenv(kKnob, "", 1);
  bool ok = open_fails_with("TESSERA_MPI_RANKS_PER_NODE is set but empty");
  // Empty on one rank, unset on the others: the disagreement says "set but empty"
  unsetenv(kKnob);
  if (world_size() > 1) {
    if (world_rank() == world_size() - 1) setenv(kKnob, "", 1);
    ok = open_fails_with("TESSERA_MPI_RANKS_PER_NODE is '' (set but empty) on rank " +
                         std::to_string(world_size() - 1) + " but unset on rank 0") &&
         ok;
  }
  if (saved) setenv(kKnob, restore.c_str(), 1);
  else unsetenv(kKnob);
  REQUIRE(all_ranks(ok));
}
