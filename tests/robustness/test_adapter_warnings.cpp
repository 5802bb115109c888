// The adapter reports what may be wrong with an image that rendered (render_warnings of the
// stats summed over ranks) in RenderResult::warnings on rank 0; a warning never fails a render.
#include "insitu_test_support.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;

namespace {
/// A 16^3 blob on a grid of spacing 0.1 (a 1.5-unit box centred at 0.75).
tessera_grid grid_01(int n) {
  tessera_grid g = unit_grid(n);
  for (double& h : g.spacing) h = 0.1;
  return g;
}
}  // namespace

TEST_CASE("adapter: a render whose paths hit a loop guard succeeds with a warning", "[robustness][insitu]") {
  TempDir dir;
  // Far camera, tiny field of view, opaque medium: some free-flight steps round to nothing
  // at t ~ 1e11 (tests/robustness/test_loops.cpp has the same scene through core).
  const std::string far =
      "    camera: {position: [1e11, 0.75, 0.75], look_at: center, up: [0, 0, 1], fov: 5e-10}\n"
      "    transfer_function: {range: auto, density_scale: 1e308, opacity: [[0, 1], [1, 1]], diffuse: viridis}\n";
  const std::string renders = render_yaml("far", "", far, "density", 16, 2) + render_yaml("near", "");
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), renders));
  constexpr int n = 16;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);
  const tessera_grid grid = grid_01(n);

  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  REQUIRE(adapter.execute(0, 0.0, grid, {&field, 1}) == TESSERA_OK);
  const auto& results = adapter.last_results();
  REQUIRE(results.size() == 2);
  const RenderResult& bad = results[0].name == "far" ? results[0] : results[1];
  const RenderResult& good = results[0].name == "far" ? results[1] : results[0];
  CHECK(bad.status == TESSERA_OK);
  CHECK(bad.stats.stalled_paths > 0);
  REQUIRE(bad.warnings.size() == 1);
  CHECK_THAT(bad.warnings[0], Contains("loop guard"));
  CHECK(good.status == TESSERA_OK);
  CHECK(good.warnings.empty());
}
