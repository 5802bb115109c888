// tessera_field_unchanged / Adapter::field_unchanged: a field marked unchanged is not read
// again at the next execute (RenderResult::field_passes == 0) and renders bit-identically;
// without the mark, or with another layout despite it, the field is read again; renders and
// Cinema cameras of one call share one pass; the C API rejects bad arguments cleanly.
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;

namespace {

constexpr int kN = 16;

/// An adapter over `renders` (YAML), quiet, opened in dir.
void open_quiet(Adapter& adapter, const TempDir& dir, const std::string& renders) {
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), renders));
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
}

/// The image a fresh adapter renders for these values at this step.
tessera::Image fresh_image(const std::vector<float>& values, int n, std::int64_t step) {
  TempDir dir;
  Adapter adapter;
  open_quiet(adapter, dir, render_yaml("main", ""));
  const tessera_field f = dense_field("density", values.data(), n);
  REQUIRE(adapter.execute(step, 0.0, unit_grid(n), {&f, 1}) == TESSERA_OK);
  REQUIRE(adapter.last_results().at(0).field_passes == 1);
  return *adapter.last_image("main");
}

}  // namespace

TEST_CASE("field_unchanged: the next execute skips the field pass, same image", "[insitu][summary]") {
  TempDir dir;
  Adapter adapter;
  open_quiet(adapter, dir, render_yaml("main", ""));
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);

  REQUIRE(adapter.execute(3, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);
  CHECK(adapter.last_results().at(0).field_passes == 1);
  const tessera::Image first = *adapter.last_image("main");

  // Marked: no pass, and the image of a fresh adapter (same step: same random streams)
  REQUIRE(adapter.field_unchanged("density") == TESSERA_OK);
  REQUIRE(adapter.execute(3, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);
  CHECK(adapter.last_results().at(0).field_passes == 0);
  CHECK(same_pixels(first, *adapter.last_image("main")));

  // One-shot: the following execute reads the field again
  REQUIRE(adapter.execute(3, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);
  CHECK(adapter.last_results().at(0).field_passes == 1);
  CHECK(same_pixels(first, *adapter.last_image("main")));

  // Marked at every step: kept across a chain of calls
  for (int step = 4; step < 7; ++step) {
    REQUIRE(adapter.field_unchanged("density") == TESSERA_OK);
    REQUIRE(adapter.execute(step, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);
    CHECK(adapter.last_results().at(0).field_passes == 0);
  }
  CHECK(same_pixels(fresh_image(sim, kN, 6), *adapter.last_image("main")));
}

TEST_CASE("field_unchanged: an unmarked call in between, even one that renders nothing, drops "
          "the summary",
          "[insitu][summary]") {
  TempDir dir;
  Adapter adapter;
  open_quiet(adapter, dir, render_yaml("main", "{every: 2}"));
  std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  REQUIRE(adapter.execute(2, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);
  REQUIRE(adapter.last_results().size() == 1);

  // Step 3 renders nothing and is not marked: the simulation may have changed the values
  const std::vector<float> moved = to_float(blob_values(kN, 0.3));
  std::copy(moved.begin(), moved.end(), sim.begin());
  REQUIRE(adapter.execute(3, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);
  CHECK(adapter.last_results().empty());
  // Step 4 is marked (unchanged since step 3), but step 2's summary is of older values
  REQUIRE(adapter.field_unchanged("density") == TESSERA_OK);
  REQUIRE(adapter.execute(4, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);
  CHECK(adapter.last_results().at(0).field_passes == 1);
  CHECK(same_pixels(fresh_image(moved, kN, 4), *adapter.last_image("main")));
}

TEST_CASE("field_unchanged: another pointer or shape despite the mark is read again", "[insitu][summary]") {
  TempDir dir;
  Adapter adapter;
  open_quiet(adapter, dir, render_yaml("main", ""));
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  REQUIRE(adapter.execute(1, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);

  SECTION("other values at another address") {
    const std::vector<float> other = to_float(blob_values(kN, 0.3));
    const tessera_field f2 = dense_field("density", other.data(), kN);
    REQUIRE(adapter.field_unchanged("density") == TESSERA_OK);
    REQUIRE(adapter.execute(1, 0.0, unit_grid(kN), {&f2, 1}) == TESSERA_OK);
    CHECK(adapter.last_results().at(0).field_passes == 1);
    CHECK(same_pixels(fresh_image(other, kN, 1), *adapter.last_image("main")));
  }
  SECTION("a smaller grid at the same address") {
    constexpr int m = kN - 4;
    const tessera_field f2 = dense_field("density", sim.data(), m);
    REQUIRE(adapter.field_unchanged("density") == TESSERA_OK);
    REQUIRE(adapter.execute(1, 0.0, unit_grid(m), {&f2, 1}) == TESSERA_OK);
    CHECK(adapter.last_results().at(0).field_passes == 1);
    const std::vector<float> head(sim.begin(), sim.begin() + m * m * m);
    CHECK(same_pixels(fresh_image(head, m, 1), *adapter.last_image("main")));
  }
  SECTION("ghost layers at the same address") {
    tessera_field f2 = field;
    for (int a = 0; a < 3; ++a) f2.ghosts_lo[a] = f2.ghosts_hi[a] = 1;
    REQUIRE(adapter.field_unchanged("density") == TESSERA_OK);
    REQUIRE(adapter.execute(1, 0.0, unit_grid(kN - 2), {&f2, 1}) == TESSERA_OK);
    CHECK(adapter.last_results().at(0).field_passes == 1);
  }
}

TEST_CASE("one pass per field and call: several renders and Cinema cameras share it", "[insitu][summary]") {
  TempDir dir;
  Adapter adapter;
  const std::string cinema =
      "    output: {file: \"{name}_{step:03d}\", formats: [exr], cinema: {azimuth: [0, 120], elevation: [0, 45]}}\n";
  const std::string tf_fixed =
      "    transfer_function: {range: [0, 250], density_scale: 40, opacity: [[0, 0], [1, 1]], diffuse: viridis}\n";
  open_quiet(adapter, dir,
             render_yaml("orbit", "", cinema, "density", 12, 1) + render_yaml("second", "", tf_fixed) +
                 render_yaml("temp", "", "", "temperature") +
                 render_yaml("coarse", "", "    integrator: {macrocell: 3}\n"));
  const std::vector<float> density = to_float(blob_values(kN));
  const std::vector<float> temperature = to_float(blob_values(kN, 0.3));
  const tessera_field fields[2] = {dense_field("density", density.data(), kN),
                                   dense_field("temperature", temperature.data(), kN)};
  REQUIRE(adapter.execute(1, 0.0, unit_grid(kN), fields) == TESSERA_OK);
  const auto& r = adapter.last_results();
  REQUIRE(r.size() == 4);
  CHECK(r[0].field_passes == 1);  // the main camera and 4 Cinema views
  CHECK(r[1].field_passes == 0);  // same field, same macrocell edge
  CHECK(r[2].field_passes == 1);  // another field
  CHECK(r[3].field_passes == 1);  // another macrocell edge
  CHECK(r[0].prepare_seconds > 0.0);

  // Only temperature marked: density is read again, once per edge
  REQUIRE(adapter.field_unchanged("temperature") == TESSERA_OK);
  REQUIRE(adapter.execute(2, 0.0, unit_grid(kN), fields) == TESSERA_OK);
  CHECK(r.at(0).field_passes == 1);
  CHECK(r.at(1).field_passes == 0);
  CHECK(r.at(2).field_passes == 0);
  CHECK(r.at(3).field_passes == 1);
  // Both marked: no pass at all
  REQUIRE(adapter.field_unchanged("temperature") == TESSERA_OK);
  REQUIRE(adapter.field_unchanged("density") == TESSERA_OK);
  REQUIRE(adapter.execute(3, 0.0, unit_grid(kN), fields) == TESSERA_OK);
  for (const RenderResult& x : adapter.last_results()) CHECK(x.field_passes == 0);
}

TEST_CASE("field_unchanged: bad arguments give a status and a message", "[insitu][summary][c_api]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("main", "")));

  CHECK(tessera_field_unchanged(nullptr, "density") == TESSERA_ERROR_CONFIG);
  CHECK(std::string(tessera_last_error(nullptr)).find("adapter is NULL") != std::string::npos);

  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  CHECK(tessera_field_unchanged(a, nullptr) == TESSERA_ERROR_DATA);
  CHECK(std::string(tessera_last_error(a)).find("NULL") != std::string::npos);
  CHECK(tessera_field_unchanged(a, "pressure") == TESSERA_ERROR_DATA);
  const std::string msg = tessera_last_error(a);
  CHECK(msg.find("'pressure'") != std::string::npos);
  CHECK(msg.find("'density'") != std::string::npos);
  CHECK(tessera_field_unchanged(a, "density") == TESSERA_OK);
  CHECK(std::string(tessera_last_error(a)).empty());
  CHECK(tessera_close(a) == TESSERA_OK);

  Adapter closed;
  CHECK(closed.field_unchanged("density") == TESSERA_ERROR_CONFIG);
  CHECK(closed.last_error().find("not open") != std::string::npos);
}
