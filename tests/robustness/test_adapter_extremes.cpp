// The adapter's own inputs at their extremes: the grid descriptor a simulation passes
// (spacing, origin) and numeric keys the kernels use. Each call returns within seconds with
// OK or an error that names the real fault, never a hang, never another key's name.
#include "insitu_test_support.h"

#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <limits>

using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
using Clock = std::chrono::steady_clock;

namespace {
struct Outcome {
  tessera_status status;
  std::string error;
  double seconds;
};

/// One execute of a 16^3 blob with `grid` changed by `edit`, through the C API.
template <class Edit>
Outcome execute_with(const std::string& renders, Edit&& edit) {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), renders, "  time_limit: 30\n"));
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  constexpr int n = 16;
  const std::vector<float> v = to_float(blob_values(n));
  const tessera_field f = dense_field("density", v.data(), n);
  tessera_grid g = unit_grid(n);
  edit(g);
  const auto t0 = Clock::now();
  const tessera_status s = tessera_execute(a, 0, 0.0, &g, &f, 1);
  Outcome o{s, tessera_last_error(a), std::chrono::duration<double>(Clock::now() - t0).count()};
  CHECK(tessera_close(a) == TESSERA_OK);
  return o;
}
}  // namespace

TEST_CASE("adapter: grid spacing and origin at their extremes fail naming the grid", "[robustness][insitu]") {
  const std::string r = render_yaml("r", "", "", "density", 16, 1);
  struct Case {
    const char* what;
    void (*edit)(tessera_grid&);
  };
  const Case cases[] = {
      {"spacing 1e308", [](tessera_grid& g) { g.spacing[0] = 1e308; }},
      {"spacing 1e-300", [](tessera_grid& g) { g.spacing[1] = 1e-300; }},
      {"spacing 0", [](tessera_grid& g) { g.spacing[2] = 0.0; }},
      {"spacing -1", [](tessera_grid& g) { g.spacing[0] = -1.0; }},
      {"spacing NaN", [](tessera_grid& g) { g.spacing[0] = std::nan(""); }},
      {"origin 1e308", [](tessera_grid& g) { g.origin[0] = 1e308; }},
      {"origin inf", [](tessera_grid& g) { g.origin[2] = std::numeric_limits<double>::infinity(); }},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const Outcome o = execute_with(r, c.edit);
    INFO(o.error);
    CHECK(o.status == TESSERA_ERROR_DATA);
    CHECK(o.seconds < 20.0);
    CHECK_THAT(o.error, Contains("spacing") || Contains("origin"));
    CHECK_THAT(o.error, !Contains("light") && !Contains("parallel") && !Contains("camera"));
  }
}

TEST_CASE("adapter: density_scale 1e308 renders in bounded time", "[robustness][insitu]") {
  const std::string tf =
      "    transfer_function: {range: auto, density_scale: 1e308, opacity: [[0, 1e308], [1, 1e308]], "
      "diffuse: viridis}\n";
  const Outcome o = execute_with(render_yaml("r", "", tf, "density", 16, 2), [](tessera_grid&) {});
  INFO(o.error);
  CHECK(o.status == TESSERA_OK);
  CHECK(o.seconds < 20.0);
}
