// A keyframed camera in the adapter: each step renders the camera of that step (a keyframe's
// step: its static camera, bit for bit), a Cinema database works beside it (its views look at
// the data centre from the step's camera distance), and a step whose pose makes no camera
// fails that render's call only.
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/image_io.h>

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace tessera::insitu;
using namespace tessera::insitu::test;

TEST_CASE("a keyframed camera in the adapter: the camera of each step, Cinema views included", "[insitu][keyframes]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string cinema = "    output: {file: \"{name}_{step:03d}\", formats: [exr, png], "
                             "cinema: {azimuth: [0, 90], elevation: [10]}}\n";
  // Keyframes at steps 2 and 6; at step 6 the camera is the second keyframe's
  const std::string keyed =
      "    camera: {keyframes: [{step: 2, position: {orbit: {azimuth: 10, elevation: 20, distance: "
      "3}}, fov: 40}, {step: 6, position: {orbit: {azimuth: 100, elevation: 35, distance: 2.5}}, "
      "look_at: [0.5, 0.4, 0.5], fov: 30}], interpolation: smooth}\n";
  const std::string fixed = "    camera: {position: {orbit: {azimuth: 100, elevation: 35, distance: 2.5}}, "
                            "look_at: [0.5, 0.4, 0.5], fov: 30}\n";
  const std::string renders = render_yaml("keyed", "{every: 1}", keyed + cinema, "density", 12, 1) +
                              render_yaml("fixed", "{every: 1}", fixed + cinema, "density", 12, 1);
  const std::string cfg = dir.write("a.yaml", config_yaml(out, renders));
  constexpr int n = 8;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);

  // Steps 1..8: held before step 2, moving up to step 6, held after it
  std::vector<tessera::Image> images;
  for (int step = 1; step <= 8; ++step) {
    REQUIRE(adapter.execute(step, 0.1 * step, unit_grid(n), {&field, 1}) == TESSERA_OK);
    images.push_back(*adapter.last_image("keyed"));
    if (step == 6) CHECK(same_pixels(images.back(), *adapter.last_image("fixed")));
  }
  // The frame number differs per step, so even a held camera's noise differs; the moving steps'
  // images differ from one another, and every step wrote its files
  for (int step = 2; step < 6; ++step) {
    INFO("step " << step);
    CHECK_FALSE(same_pixels(images[static_cast<std::size_t>(step - 1)], images[static_cast<std::size_t>(step)]));
  }
  for (int step = 1; step <= 8; ++step) {
    const std::string base = out + "/keyed_00" + std::to_string(step);
    CHECK(fs::exists(base + ".png"));
    CHECK(fs::exists(base + ".exr"));
  }

  // Cinema: the views of step 6 are the fixed camera's (same distance from the centre); data.csv
  // lists every view of every step
  for (const char* view : {"_phi_0_theta_10.exr", "_phi_90_theta_10.exr"}) {
    INFO(view);
    CHECK(same_pixels(tessera::read_exr(out + "/keyed.cdb/keyed_006" + view),
                      tessera::read_exr(out + "/fixed.cdb/fixed_006" + view)));
  }
  std::ifstream csv(out + "/keyed.cdb/data.csv");
  std::vector<std::string> lines;
  for (std::string l; std::getline(csv, l);) lines.push_back(l);
  REQUIRE(lines.size() == 1 + 8 * 2);
  CHECK(lines[0] == "time,phi,theta,FILE");
  CHECK(lines.back() == "0.8,90,10,keyed_008_phi_90_theta_10.png");
}

TEST_CASE("a keyframed pose that makes no camera fails that step's render only", "[insitu][keyframes]") {
  TempDir dir;
  const std::string out = dir.file("out");
  // The camera flies through the point it looks at, at step 5
  const std::string through = "    camera: {keyframes: [{step: 0, position: [-1, 0.5, 0.5], look_at: [0.5, 0.5, 0.5]}, "
                              "{step: 10, position: [2, 0.5, 0.5], look_at: [0.5, 0.5, 0.5]}]}\n";
  const std::string renders = render_yaml("through", "{every: 1}", through, "density", 12, 1) +
                              render_yaml("other", "{every: 1}", "", "density", 12, 1);
  const std::string cfg = dir.write("a.yaml", config_yaml(out, renders));
  constexpr int n = 8;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  REQUIRE(adapter.execute(4, 0.4, unit_grid(n), {&field, 1}) == TESSERA_OK);
  CHECK(adapter.execute(5, 0.5, unit_grid(n), {&field, 1}) == TESSERA_ERROR_RENDER);
  REQUIRE(adapter.last_results().size() == 2);
  CHECK(adapter.last_results()[0].status == TESSERA_ERROR_RENDER);
  CHECK_THAT(adapter.last_results()[0].error,
             Catch::Matchers::Contains("camera.keyframes at step 5 (between keyframes 0 and 1, steps 0 and 10): "
                                       "position [0.5, 0.5, 0.5] equals look_at"));
  CHECK(adapter.last_results()[1].status == TESSERA_OK);
  CHECK(adapter.execute(6, 0.6, unit_grid(n), {&field, 1}) == TESSERA_OK);
}
