// Cinema image databases: an orbit of azimuth x elevation cameras per timestep, data.csv
// (Cinema Spec D) with time,phi,theta,FILE, rows appended per timestep and across runs.
#include "insitu_test_support.h"
#include "outputs/cinema.h"

#include <tessera/adapter.h>
#include <tessera/image_io.h>
#include <tessera/number_text.h>

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace tessera::insitu;
using namespace tessera::insitu::test;

namespace {

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

}  // namespace

TEST_CASE("cinema_views: orbit about the centre at the render's camera distance", "[insitu][cinema]") {
  tessera::config::CinemaSpec spec;
  spec.azimuths = {0, 90};
  spec.elevations = {0, 90};
  tessera::CameraDesc main;
  main.position = {0.5, -1.5, 0.5};  // 2 from the centre
  main.look_at = {0.0, 0.0, 0.0};
  main.up = {0, 0, 1};
  const tessera::Bounds b{tessera::Vec3(0.0), tessera::Vec3(1.0)};
  const std::vector<CinemaView> v = cinema_views(spec, main, b);
  REQUIRE(v.size() == 4);
  CHECK(v[0].phi == 0);
  CHECK(v[1].phi == 90);
  CHECK(v[2].theta == 90);
  for (const CinemaView& c : v) {
    CHECK(glm::length(c.camera.position - b.center()) == Approx(2.0));
    CHECK(c.camera.look_at == b.center());
    // up is perpendicular to the view, so the camera is valid even at the pole
    CHECK(std::abs(glm::dot(c.camera.up, c.camera.position - b.center())) < 1e-12);
  }
  CHECK(v[0].camera.position.x == Approx(2.5));  // azimuth 0: +x for up = +z
  CHECK(v[1].camera.position.y == Approx(2.5));  // azimuth 90: +y
  CHECK(v[2].camera.position.z == Approx(2.5));  // elevation 90: +z
  // phi and theta in file names and data.csv: shortest text that reads back exactly
  CHECK(tessera::format_number(30.0) == "30");
  CHECK(tessera::format_number(-12.25) == "-12.25");
}

TEST_CASE("a Cinema render writes a Spec D database, appending per timestep", "[insitu][cinema]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string extra = "    output: {file: \"{name}_{step:03d}\", formats: [png, exr], "
                            "cinema: {azimuth: [0, 120, 240], elevation: [-30, 90]}}\n";
  const std::string cfg =
      dir.write("a.yaml", config_yaml(out, render_yaml("orbit", "{every: 5}", extra, "density", 12, 1)));
  constexpr int n = 8;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);

  {
    Adapter adapter;
    adapter.set_quiet(true);
    REQUIRE(adapter.open(cfg) == TESSERA_OK);
    REQUIRE(adapter.execute(5, 0.5, unit_grid(n), {&field, 1}) == TESSERA_OK);
    const RenderResult& r = adapter.last_results().at(0);
    CHECK(r.files.size() == 2 + 6 * 2);  // the main image and 6 views, PNG + EXR each
    CHECK(r.stats.samples == 7u * 12u * 12u);
    CHECK(fs::exists(out + "/orbit_005.png"));
    REQUIRE(adapter.execute(10, 1.0, unit_grid(n), {&field, 1}) == TESSERA_OK);
  }
  const std::string cdb = out + "/orbit.cdb";
  std::vector<std::string> csv = lines_of(cdb + "/data.csv");
  REQUIRE(csv.size() == 1 + 12);
  CHECK(csv[0] == "time,phi,theta,FILE");
  CHECK(csv[1] == "0.5,0,-30,orbit_005_phi_0_theta_-30.png");
  CHECK(csv[6] == "0.5,240,90,orbit_005_phi_240_theta_90.png");
  CHECK(csv[12] == "1,240,90,orbit_010_phi_240_theta_90.png");
  for (std::size_t i = 1; i < csv.size(); ++i) {
    const std::string file = csv[i].substr(csv[i].rfind(',') + 1);
    CHECK(fs::exists(cdb + "/" + file));
  }
  // Views differ from one another
  CHECK_FALSE(same_pixels(tessera::read_exr(cdb + "/orbit_005_phi_0_theta_-30.exr"),
                          tessera::read_exr(cdb + "/orbit_005_phi_120_theta_-30.exr")));

  // A new run adds its rows to the existing database, replacing rows for the same files
  {
    Adapter adapter;
    adapter.set_quiet(true);
    REQUIRE(adapter.open(cfg) == TESSERA_OK);
    REQUIRE(adapter.execute(10, 1.0, unit_grid(n), {&field, 1}) == TESSERA_OK);
    REQUIRE(adapter.execute(15, 1.5, unit_grid(n), {&field, 1}) == TESSERA_OK);
  }
  csv = lines_of(cdb + "/data.csv");
  CHECK(csv.size() == 1 + 18);
  CHECK(csv.back() == "1.5,240,90,orbit_015_phi_240_theta_90.png");
}

TEST_CASE("a moving orbit in the adapter: the static orbit of the step, Cinema views included", "[insitu][cinema]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string cinema = "    output: {file: \"{name}_{step:03d}\", formats: [exr], "
                             "cinema: {azimuth: [0, 90], elevation: [10]}}\n";
  // At step 5: azimuth 10 + 4 * 5 = 30, elevation 40 - 3 * 5 = 25, distance 2 + 0.25 * 5 = 3.25
  const std::string moving = "    camera: {position: {orbit: {azimuth: {start: 10, per_step: 4}, elevation: {start: "
                             "40, per_step: -3}, distance: {start: 2, per_step: 0.25}}}, fov: 40}\n";
  const std::string fixed = "    camera: {position: {orbit: {azimuth: 30, elevation: 25, distance: 3.25}}, fov: 40}\n";
  const std::string renders = render_yaml("moving", "{every: 1}", moving + cinema, "density", 12, 1) +
                              render_yaml("fixed", "{every: 1}", fixed + cinema, "density", 12, 1);
  const std::string cfg = dir.write("a.yaml", config_yaml(out, renders));
  constexpr int n = 8;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  REQUIRE(adapter.execute(5, 0.5, unit_grid(n), {&field, 1}) == TESSERA_OK);
  CHECK(same_pixels(*adapter.last_image("moving"), *adapter.last_image("fixed")));
  // The views keep their angles and take the camera's distance of the step
  for (const char* view : {"_phi_0_theta_10.exr", "_phi_90_theta_10.exr"}) {
    INFO(view);
    CHECK(same_pixels(tessera::read_exr(out + "/moving.cdb/moving_005" + view),
                      tessera::read_exr(out + "/fixed.cdb/fixed_005" + view)));
  }
  // Step 6 moves the camera
  REQUIRE(adapter.execute(6, 0.6, unit_grid(n), {&field, 1}) == TESSERA_OK);
  CHECK_FALSE(same_pixels(*adapter.last_image("moving"), *adapter.last_image("fixed")));
  // At step -17 the elevation is 91: that call fails for this render, with the value and step
  CHECK(adapter.execute(-17, 0.0, unit_grid(n), {&field, 1}) == TESSERA_ERROR_RENDER);
  REQUIRE(adapter.last_results().size() == 2);
  CHECK(adapter.last_results()[0].status == TESSERA_ERROR_RENDER);
  CHECK_THAT(adapter.last_results()[0].error,
             Catch::Matchers::Contains("orbit elevation {start: 40, per_step: -3} is 91 at step -17"));
  CHECK(adapter.last_results()[1].status == TESSERA_OK);
}
