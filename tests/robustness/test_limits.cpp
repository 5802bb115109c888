// Robustness: tessera.time_limit and tessera.memory_limit_mb (docs/insitu.md and docs/cli.md,
// "Limits and failure"), through the adapter and the CLI. Times are asserted only as
// generous bounds ("finishes rather than hangs", "fails before allocating").
#include "../insitu/insitu_test_support.h"
#include "cli_run.h"

#include <tessera/film.h>
#include <tessera/memory_estimate.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// A 16^3 float32 blob as a raw file and a CLI scene with one render (64x64, huge spp).
void write_cli_scene(const TempDir& dir, const std::string& global) {
  const std::vector<float> v = to_float(blob_values(16));
  std::ofstream(dir.file("blob.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  dir.write("scene.yaml", "tessera:\n  output_dir: results\n" + global +
                              "volume: {file: blob.raw, dims: [16, 16, 16], dtype: float32, spacing: [0.1, 0.1, 0.1]}\n"
                              "renders:\n" +
                              render_yaml("heavy", "", "", "", 64, 1000000));
}

using Run = tessera_test::CliRun;
using tessera_test::count_files;
using tessera_test::run_cli;

/// One execute of a 16^3 blob under `config_text` (whose render `name` passes its time limit
/// of `limit_s`): TESSERA_ERROR_RENDER within 15 s naming the limit, and no image written.
void expect_time_limit_failure(const TempDir& dir, const std::string& config_text, const std::string& name,
                               int limit_s) {
  const std::string out = dir.file("out");
  const std::string cfg = dir.write("a.yaml", config_text);
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);
  const auto t0 = Clock::now();
  CHECK(tessera_execute(a, 0, 0.0, &g, &f, 1) == TESSERA_ERROR_RENDER);
  CHECK(seconds_since(t0) < 15.0);
  CHECK_THAT(std::string(tessera_last_error(a)),
             Contains("passed tessera.time_limit = " + std::to_string(limit_s) + " s"));
  CHECK_FALSE(fs::exists(out + "/" + name + "_0000.exr"));
  CHECK(tessera_close(a) == TESSERA_OK);
}

}  // namespace

TEST_CASE("time_limit: a render far too long fails after the limit, writes nothing, and the next call renders",
          "[robustness][limits]") {
  TempDir dir;
  const std::string out = dir.file("out");
  // `heavy` fires at step 0 only; `light` at every step
  const std::string cfg =
      dir.write("a.yaml", config_yaml(out,
                                      render_yaml("heavy", "{at: [0]}", "", "density", 64, 1000000) +
                                          render_yaml("light", "", "", "density", 16, 1),
                                      "  time_limit: 2\n"));
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);

  const auto t0 = Clock::now();
  CHECK(tessera_execute(a, 0, 0.0, &g, &f, 1) == TESSERA_ERROR_RENDER);
  const double took = seconds_since(t0);
  const std::string err = tessera_last_error(a);
  CHECK_THAT(err,
             Contains("render 'heavy' at step 0") && Contains("tessera.time_limit = 2 s") && Contains("tiles done"));
  CHECK(took > 1.5);
  CHECK(took < 15.0);
  CHECK_FALSE(fs::exists(out + "/heavy_0000.exr"));
  CHECK(count_files(out, ".tmp") == 0);
  CHECK(fs::exists(out + "/light_0000.exr"));  // the other render of the call went on

  // The simulation goes on: the next call renders
  CHECK(tessera_execute(a, 1, 0.1, &g, &f, 1) == TESSERA_OK);
  CHECK(fs::exists(out + "/light_0001.exr"));
  CHECK(tessera_close(a) == TESSERA_OK);
}

TEST_CASE("time_limit: one endless path inside a tile stops too", "[robustness][limits]") {
  // The camera inside a dense, white medium with max_bounces 10^6: every path random-walks
  // until max_bounces (minutes for this one 16x16 tile at 1 spp without a limit). Tiles and
  // passes are too coarse here: the path itself polls the deadline every 256 collisions.
  TempDir dir;
  const std::string extra = "    camera: {position: center, look_at: [0, 0, 0], up: [0, 0, 1], fov: 40}\n"
                            "    transfer_function: {range: auto, density_scale: 1e308, opacity: [[0, 1], [1, 1]], "
                            "diffuse: [[0, [1, 1, 1]]]}\n"
                            "    integrator: {scattering: multiple, max_bounces: 1000000, shading: phase, tile: 16}\n";
  expect_time_limit_failure(
      dir, config_yaml(dir.file("out"), render_yaml("walk", "", extra, "density", 16, 1), "  time_limit: 1\n"), "walk",
      1);
}

TEST_CASE("time_limit: adaptive sampling stops too - the preview in prepare and then the tiles",
          "[robustness][limits]") {
  TempDir dir;
  std::string render = render_yaml("adaptive", "", "", "density", 64, 1000000);
  const std::string spp = "spp: 1000000}";
  render.replace(render.find(spp), spp.size(), "spp: 1000000, target_error: 0.0001}");
  expect_time_limit_failure(dir, config_yaml(dir.file("out"), render, "  time_limit: 1\n"), "adaptive", 1);
}

TEST_CASE("time_limit covers every Cinema view of a render", "[robustness][limits]") {
  TempDir dir;
  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);
  const std::string cinema = "    output: {cinema: {azimuth: [0, 60, 120, 180, 240, 300], elevation: [0, 30]}}\n";

  // Calibration: the time of one camera (no limit)
  double one_view = 0.0;
  {
    tessera::insitu::Adapter ad;
    ad.set_quiet(true);
    REQUIRE(ad.open(dir.write("c.yaml", config_yaml(dir.file("c"), render_yaml("sweep", "", "", "density", 48, 64))),
                    -1) == TESSERA_OK);
    REQUIRE(ad.execute(0, 0.0, g, std::span<const tessera_field>(&f, 1)) == TESSERA_OK);
    one_view = ad.last_results().at(0).render_seconds;
  }
  // A limit of about three cameras' time: the main image fits, the 12 views do not
  const double limit = std::max(0.2, 3.0 * one_view);
  char global[64];
  std::snprintf(global, sizeof global, "  time_limit: %.3f\n", limit);
  const std::string out = dir.file("out");
  const std::string cfg =
      dir.write("a.yaml", config_yaml(out, render_yaml("sweep", "", cinema, "density", 48, 64), global));
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  const auto t0 = Clock::now();
  CHECK(tessera_execute(a, 0, 0.0, &g, &f, 1) == TESSERA_ERROR_RENDER);
  CHECK(seconds_since(t0) < limit + 10.0);
  CHECK_THAT(std::string(tessera_last_error(a)), Contains("passed tessera.time_limit"));
  CHECK(count_files(out, ".tmp") == 0);
  tessera_close(a);
}

TEST_CASE("memory_limit_mb: a 16384^2 image fails before allocating, with the estimate and the limit",
          "[robustness][limits]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string cfg = dir.write(
      "a.yaml", config_yaml(out, render_yaml("huge", "", "", "density", 16384, 1), "  memory_limit_mb: 1024\n"));
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);
  const auto t0 = Clock::now();
  CHECK(tessera_execute(a, 0, 0.0, &g, &f, 1) == TESSERA_ERROR_RENDER);
  CHECK(seconds_since(t0) < 2.0);  // nothing of 21 GiB was touched
  const std::string err = tessera_last_error(a);
  // film: 16384^2 pixels x 64 bytes (PixelSums) = 16 GiB
  CHECK_THAT(err, Contains("render 'huge'") && Contains("needs an estimated") && Contains("film 16 GiB") &&
                      Contains("more than tessera.memory_limit_mb = 1024 MiB"));
  CHECK_FALSE(fs::exists(out + "/huge_0000.exr"));
  tessera_close(a);
}

TEST_CASE("memory estimate of a known configuration", "[robustness][limits]") {
  tessera::RenderFootprint f;
  f.width = 100;
  f.height = 50;
  f.tile = 10;
  f.threads = 2;
  f.formats = {tessera::ImageFormat::Exr, tessera::ImageFormat::Png};
  f.variance = true;
  f.field_dims[0] = f.field_dims[1] = f.field_dims[2] = 33;  // 2^3 cells of edge 16
  f.macrocell_edge = 16;
  f.envmap_width = 64;
  f.envmap_height = 32;
  const tessera::MemoryEstimate e = tessera::estimate_render_memory(f);
  const auto part = [&](const std::string& name) -> std::uint64_t {
    for (const auto& p : e.parts)
      if (p.name == name) return p.bytes;
    return 0;
  };
  CHECK(part("film") == 5000u * sizeof(tessera::PixelSums));
  // RGBA + variance floats, the 8-bit PNG, OpenEXR's 16-line buffers (raw and compressed)
  CHECK(part("images") == 5000u * 5 * 4 + 5000u * 4 + 100u * 5 * 4 * 2 * 16);
  CHECK(part("majorant grid") > 0);
  CHECK(part("majorant grid") < 8 * 64);
  CHECK(part("envmap") == 64u * 32 * 72);
  CHECK(part("tile lists") > 0);
  std::uint64_t sum = 0;
  for (const auto& p : e.parts) sum += p.bytes;
  CHECK(e.total() == sum);
  CHECK_THAT(e.describe(), Contains("film 312 KiB"));
  // Each format alone: its writer's part only (none: the float image alone)
  const auto images = [&](std::vector<tessera::ImageFormat> formats) {
    tessera::RenderFootprint g = f;
    g.formats = std::move(formats);
    for (const auto& p : tessera::estimate_render_memory(g).parts)
      if (p.name == "images") return p.bytes;
    return std::uint64_t{0};
  };
  CHECK(images({tessera::ImageFormat::Png}) == 5000u * 5 * 4 + 5000u * 4);
  CHECK(images({tessera::ImageFormat::Exr}) == 5000u * 5 * 4 + 100u * 5 * 4 * 2 * 16);
  CHECK(images({}) == 5000u * 5 * 4);

  // 16384^2, EXR and PNG: about 21 GiB
  tessera::RenderFootprint big;
  big.width = big.height = 16384;
  const double gib = static_cast<double>(tessera::estimate_render_memory(big).total()) / (1ull << 30);
  CHECK(gib > 20.0);
  CHECK(gib < 23.0);

  // Default limit: half of physical memory over the node's ranks
  const std::uint64_t phys = tessera::physical_memory_bytes();
  REQUIRE(phys > 0);
  CHECK(tessera::default_memory_limit_bytes(1) == phys / 2);
  CHECK(tessera::default_memory_limit_bytes(4) == phys / 2 / 4);
  CHECK(tessera::format_bytes(512) == "512 B");
  CHECK(tessera::format_bytes(21ull << 30) == "21 GiB");
}

#ifdef TESSERA_RENDER_EXE
TEST_CASE("CLI: --time-limit and tessera.time_limit fail the render, exit non-zero, write nothing",
          "[robustness][limits][cli]") {
  TempDir dir;
  write_cli_scene(dir, "");
  Run r = run_cli(dir, "scene.yaml --quiet --threads 2 --time-limit 2");
  CHECK(r.status == 1);
  CHECK(r.seconds > 1.5);
  CHECK(r.seconds < 15.0);
  CHECK_THAT(r.err, Contains("tessera-render: error: render 'heavy' passed --time-limit = 2 s after") &&
                        Contains("tiles done"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK(count_files(dir.file("results"), "heavy") == 0);

  write_cli_scene(dir, "  time_limit: 2\n");
  r = run_cli(dir, "scene.yaml --quiet --threads 2");
  CHECK(r.status == 1);
  CHECK(r.seconds < 15.0);
  CHECK_THAT(r.err, Contains("passed tessera.time_limit = 2 s"));
  CHECK(count_files(dir.file("results"), "heavy") == 0);
}

TEST_CASE("CLI: tessera.memory_limit_mb fails a 16384^2 render before allocating", "[robustness][limits][cli]") {
  TempDir dir;
  write_cli_scene(dir, "  memory_limit_mb: 2048\n");
  const Run r = run_cli(dir, "scene.yaml --quiet --width 16384 --height 16384 --spp 1");
  CHECK(r.status == 1);
  CHECK(r.seconds < 5.0);
  CHECK_THAT(r.err, Contains("render 'heavy' needs an estimated") && Contains("film 16 GiB") &&
                        Contains("tessera.memory_limit_mb = 2048 MiB"));
}

TEST_CASE("CLI: a volume larger than the memory limit fails before its file is read", "[robustness][limits][cli]") {
  TempDir dir;
  // A sparse 128 MiB file: costs nothing on disk, but reading it would take 128 MiB
  {
    std::ofstream(dir.file("big.raw"), std::ios::binary).put('\0');
    fs::resize_file(dir.file("big.raw"), std::uintmax_t(128) << 20);
  }
  dir.write("scene.yaml", "tessera:\n  output_dir: results\n  memory_limit_mb: 64\n"
                          "volume: {file: big.raw, dims: [1024, 1024, 32], dtype: float32}\n"
                          "renders:\n" +
                              render_yaml("r", "", "", "", 16, 1));
  const Run r = run_cli(dir, "scene.yaml --quiet");
  CHECK(r.status == 1);
  CHECK(r.seconds < 5.0);
  CHECK_THAT(r.err, Contains("1024x1024x32 values need 128 MiB, more than tessera.memory_limit_mb = 64 MiB"));
}
#endif
