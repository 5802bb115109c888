// Cinema image databases: an orbit of azimuth x elevation cameras per timestep, data.csv
// (Cinema Spec D) with time,phi,theta,FILE, rows appended per timestep and across runs.
#include "cinema.h"
#include "insitu_test_support.h"

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
