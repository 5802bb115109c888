// tessera.time_limit and tessera.memory_limit_mb across ranks: every rank stops at its next
// tile and gets the error (agreed before the gather), none hangs; the next call renders.
#include "blob_slab.h"
#include "mpi_test_support.h"

#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

using namespace tessera_mpi_test;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

std::string render_entry(const std::string& name, const std::string& trigger, int size, int spp) {
  return "  - name: " + name + "\n    field: density\n    trigger: " + trigger +
         "\n    image: {width: " + std::to_string(size) + ", height: " + std::to_string(size) +
         ", spp: " + std::to_string(spp) +
         "}\n"
         "    camera: {position: {orbit: {azimuth: 30, elevation: 25, distance: 3}}, look_at: center, up: [0, 0, 1], "
         "fov: 40}\n"
         "    transfer_function: {range: [0, 250], density_scale: 40, opacity: [[0, 0], [1, 1]], diffuse: viridis}\n"
         "    lights: [{type: sphere, position: [3, -2, 3], radius: 0.4, intensity: 20}]\n"
         "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

TEST_CASE("time_limit stops every rank and the next call renders", "[mpi][limits]") {
  SharedTempDir dir("tessera_limits_");
  const std::string out = dir.file("out");
  const std::string cfg = dir.write(
      "a.yaml", "tessera:\n  output_dir: " + out + "\n  threads: 1\n  time_limit: 2\nrenders:\n" +
                    render_entry("heavy", "{at: [0]}", 64, 1000000) + render_entry("light", "{every: 1}", 16, 1));
  BlobSlab slab;
  tessera_adapter* a = nullptr;
  REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
  const auto t0 = Clock::now();
  const tessera_status s = tessera_execute(a, 0, 0.0, &slab.grid, &slab.field, 1);
  const double took = seconds_since(t0);
  const std::string err = tessera_last_error(a);
  CHECK(all_ranks(s == TESSERA_ERROR_RENDER));
  CHECK(all_ranks(took > 1.5 && took < 15.0));
  CHECK(all_ranks(err.find("tessera.time_limit = 2 s") != std::string::npos));
  if (world_rank() == 0) {
    CHECK_FALSE(fs::exists(out + "/heavy_0000.exr"));
    CHECK(fs::exists(out + "/light_0000.exr"));
  }
  const tessera_status next = tessera_execute(a, 1, 0.1, &slab.grid, &slab.field, 1);
  CHECK(all_ranks(next == TESSERA_OK));
  if (world_rank() == 0) CHECK(fs::exists(out + "/light_0001.exr"));
  CHECK(all_ranks(tessera_close(a) == TESSERA_OK));
}

TEST_CASE("memory_limit_mb fails fast on every rank with the estimate", "[mpi][limits]") {
  SharedTempDir dir("tessera_limits_");
  const std::string out = dir.file("out");
  const std::string cfg =
      dir.write("b.yaml", "tessera:\n  output_dir: " + out + "\n  threads: 1\n  memory_limit_mb: 1024\nrenders:\n" +
                              render_entry("huge", "{every: 1}", 16384, 1));
  BlobSlab slab;
  tessera_adapter* a = nullptr;
  REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
  const auto t0 = Clock::now();
  const tessera_status s = tessera_execute(a, 0, 0.0, &slab.grid, &slab.field, 1);
  CHECK(all_ranks(s == TESSERA_ERROR_RENDER));
  CHECK(all_ranks(seconds_since(t0) < 5.0));
  const std::string err = tessera_last_error(a);
  CHECK(all_ranks(err.find("tessera.memory_limit_mb = 1024 MiB") != std::string::npos));
  if (world_size() > 1 && world_rank() == 0) CHECK(err.find("field replica") != std::string::npos);
  CHECK(all_ranks(tessera_close(a) == TESSERA_OK));
}
