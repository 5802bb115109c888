// The adapter's warnings (rank 0, RenderResult::warnings, scene_warnings.h) for a range that
// misses the data and a constant field, and the in situ cost it reports per render
// (simulation_seconds since the last render, cost_ratio).
#include "insitu_test_support.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <thread>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;

TEST_CASE("adapter warns when the range misses the data, naming both", "[insitu][warnings]") {
  TempDir dir;
  const std::string miss =
      "    transfer_function: {range: [1000, 2000], density_scale: 40, opacity: [[0, 0], [1, 1]]}\n";
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("miss", "", miss)));
  constexpr int n = 16;
  const std::vector<float> sim = to_float(blob_values(n));  // integers in [0, 250]
  const tessera_field field = dense_field("density", sim.data(), n);
  const tessera_grid grid = unit_grid(n);

  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  REQUIRE(adapter.execute(0, 0.0, grid, {&field, 1}) == TESSERA_OK);  // a warning never fails
  REQUIRE(adapter.last_results().size() == 1);
  const RenderResult& r = adapter.last_results()[0];
  CHECK(r.status == TESSERA_OK);
  CHECK(r.files.size() == 1);
  CHECK(r.stats.real_collisions == 0);
  REQUIRE(r.warnings.size() == 2);
  const float hi = *std::max_element(sim.begin(), sim.end());
  CHECK_THAT(r.warnings[0], Contains("transfer_function.range [1000, 2000] misses the data's values [0, " +
                                     std::to_string(static_cast<int>(hi)) + "]: nothing of the field is visible"));
  CHECK_THAT(r.warnings[1], Contains("nothing of the field is visible: 0 real collisions"));
}

TEST_CASE("adapter warns about a constant field (the heat demo's first frame)", "[insitu][warnings]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("flat", "")));
  constexpr int n = 12;
  const std::vector<float> sim(n * n * n, 300.0f);
  const tessera_field field = dense_field("density", sim.data(), n);
  const tessera_grid grid = unit_grid(n);

  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  REQUIRE(adapter.execute(0, 0.0, grid, {&field, 1}) == TESSERA_OK);
  REQUIRE(adapter.last_results().size() == 1);
  const RenderResult& r = adapter.last_results()[0];
  CHECK(r.status == TESSERA_OK);
  REQUIRE_FALSE(r.warnings.empty());
  CHECK_THAT(r.warnings[0], Contains("the field is constant (300)"));
}

TEST_CASE("adapter reports the simulation's time since the last render and the cost ratio", "[insitu][warnings]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("every2", "{every: 2}")));
  constexpr int n = 12;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);
  const tessera_grid grid = unit_grid(n);

  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  const auto t0 = std::chrono::steady_clock::now();  // an upper bound on what the adapter can count
  REQUIRE(adapter.execute(0, 0.0, grid, {&field, 1}) == TESSERA_OK);
  REQUIRE(adapter.last_results().size() == 1);
  {
    const RenderResult& r = adapter.last_results()[0];
    CHECK(r.simulation_seconds == 0.0);  // the first call: nothing to compare with
    CHECK(r.cost_ratio == 0.0);
  }
  // Two "steps" of 30 ms each; the render fires on the second call only (every: 2)
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  REQUIRE(adapter.execute(1, 1.0, grid, {&field, 1}) == TESSERA_OK);
  CHECK(adapter.last_results().empty());
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  REQUIRE(adapter.execute(2, 2.0, grid, {&field, 1}) == TESSERA_OK);
  const double outside_max = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  REQUIRE(adapter.last_results().size() == 1);
  const RenderResult& r = adapter.last_results()[0];
  // Both sleeps count (the call in between rendered nothing); nothing before the first render
  CHECK(r.simulation_seconds >= 0.060);
  CHECK(r.simulation_seconds <= outside_max);
  REQUIRE(r.render_seconds > 0.0);
  CHECK(r.cost_ratio == Approx(r.render_seconds / r.simulation_seconds));
}
