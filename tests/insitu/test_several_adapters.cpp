// Several adapters in one process (an Ascent port publishing two meshes, say): their outputs
// never collide (a second adapter on the same output_dir is refused at open, naming the
// first), the time one spends rendering is never another's simulation time, and
// Adapter::fires says what execute decides first.
#include "insitu_test_support.h"
#include "scoped_env.h"

#include <tessera/adapter.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;

TEST_CASE("several adapters: a second adapter on the same output_dir is refused at open, naming the first",
          "[insitu][adapters]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string a_cfg = dir.write("a.yaml", config_yaml(out, render_yaml("main", "{every: 1}")));
  const std::string b_cfg = dir.write("b.yaml", config_yaml(out, render_yaml("other", "{every: 1}")));
  Adapter a;
  a.set_quiet(true);
  REQUIRE(a.open(a_cfg) == TESSERA_OK);
  // The same directory, written alike or not
  for (const std::string& same : {std::string(), out + "/", out + "/./", dir.file("out/../out")}) {
    INFO("output_dir '" << same << "'");
    Adapter b;
    OpenOptions options;
    options.output_dir = same;
    CHECK(b.open(b_cfg, -1, options) == TESSERA_ERROR_CONFIG);
    CHECK_THAT(b.last_error(), Contains("is the output directory of another adapter open in this process") &&
                                   Contains("a.yaml") && Contains("give each adapter its own output_dir"));
    CHECK_FALSE(b.is_open());
  }
  // The C API alike
  tessera_adapter* c = nullptr;
  CHECK(tessera_open(b_cfg.c_str(), -1, &c) == TESSERA_ERROR_CONFIG);
  CHECK(c == nullptr);
  CHECK_THAT(std::string(tessera_last_error(nullptr)), Contains("another adapter open in this process"));
  // Another directory opens; once the first adapter closes, its directory is free again
  Adapter b;
  OpenOptions elsewhere;
  elsewhere.output_dir = dir.file("out_b");
  CHECK(b.open(b_cfg, -1, elsewhere) == TESSERA_OK);
  a.close();
  Adapter again;
  CHECK(again.open(b_cfg) == TESSERA_OK);
  // A refused open leaves no claim behind
  Adapter refused;
  CHECK(refused.open(b_cfg) == TESSERA_ERROR_CONFIG);
  again.close();
  CHECK(refused.open(b_cfg) == TESSERA_OK);
}

TEST_CASE("several adapters: the time one adapter renders is never another's simulation time",
          "[insitu][adapters][budget]") {
  tessera_test::ScopedEnv no_fake_clock("TESSERA_TEST_CLOCK", std::nullopt);
  TempDir dir;
  constexpr int n = 16;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);
  const tessera_grid grid = unit_grid(n);
  // a: a small render under a budget; b: a large one, no budget
  Adapter a, b;
  a.set_quiet(true);
  b.set_quiet(true);
  REQUIRE(a.open(dir.write("a.yaml", config_yaml(dir.file("a"), render_yaml("small", "{every: 1}", "", "density", 8, 1),
                                                 "  budget: 0.5\n"))) == TESSERA_OK);
  REQUIRE(b.open(dir.write("b.yaml", config_yaml(dir.file("b"), render_yaml("large", "{every: 1}", "", "density", 160,
                                                                            16)))) == TESSERA_OK);
  REQUIRE(a.execute(0, 0.0, grid, {&field, 1}) == TESSERA_OK);
  // Between a's two calls the process spends its time inside b
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(b.execute(0, 0.0, grid, {&field, 1}) == TESSERA_OK);
  const double in_b = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  REQUIRE(a.execute(1, 0.1, grid, {&field, 1}) == TESSERA_OK);
  REQUIRE(a.last_results().size() == 1);
  const double a_sim = a.last_results()[0].simulation_seconds;
  INFO("b rendered " << in_b << " s; a counted " << a_sim << " s of simulation");
  REQUIRE(in_b > 0.0);
  // (what is left is the test's own code between the calls: microseconds against b's render)
  CHECK(a_sim < 0.25 * in_b);
}

TEST_CASE("Adapter::fires says whether execute would evaluate a render, from the step alone", "[insitu][adapters]") {
  TempDir dir;
  constexpr int n = 8;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);
  Adapter a;
  a.set_quiet(true);
  CHECK_FALSE(a.fires(0, false));  // not open
  REQUIRE(a.open(dir.write("a.yaml", config_yaml(dir.file("out"),
                                                 render_yaml("three", "{every: 3}", "", "density", 8, 1) +
                                                     render_yaml("five", "{at: [5]}", "", "density", 8, 1),
                                                 "  render_final_step: true\n"))) == TESSERA_OK);
  for (std::int64_t step = 0; step <= 12; ++step) {
    INFO("step " << step);
    const bool fires = a.fires(step, false);
    CHECK(fires == (step % 3 == 0 || step == 5));
    REQUIRE(a.execute(step, 0.0, unit_grid(n), {&field, 1}) == TESSERA_OK);
    CHECK(fires == !a.last_results().empty());
    CHECK(a.fires(step, true));  // render_final_step: every render on the final step
  }
  // A `when` trigger looks at the field at every step
  Adapter w;
  REQUIRE(w.open(dir.write("w.yaml", config_yaml(dir.file("w"), render_yaml("hot", "{when: {above: 1e9}}")))) ==
          TESSERA_OK);
  CHECK(w.fires(7, false));
  w.close();
  CHECK_FALSE(w.fires(7, false));
}
