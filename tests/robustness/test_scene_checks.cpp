// Nothing silent: scene values at the extremes of every numeric key either render (finite
// image, within seconds) or fail with a message naming the real key; tiny lights no longer
// discard samples; render_warnings; the threads statistic is the number actually used.
#include <tessera/config/build_scene.h>
#include <tessera/image_io.h>
#include <tessera/loop_bounds.h>
#include <tessera/render.h>
#include <tessera/stats.h>

#include "light_lookup.h"
#include "loop_support.h"

#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <string>
#include <thread>
#include <vector>

using Catch::Matchers::Contains;
using tessera::Color;
using tessera::Vec3;
using namespace tessera_test;

namespace {
constexpr double kBoundSeconds = 20.0;
}  // namespace

TEST_CASE("messages name the real key: spacing, camera position", "[robustness][scene]") {
  const std::vector<float> v = ball_field();
  const auto view = ball_view(v);
  SECTION("spacing 1e308 is a spacing fault, not a sphere light's") {
    tessera::SceneDesc s = ball_scene();
    s.geometry.spacing = Vec3(1e308);
    tessera::nth_light<tessera::SphereLightDesc>(s.lights, 0).center =
        Vec3(INFINITY);  // what an orbit against the bounds resolves to
    try {
      (void)tessera::prepare(view, s);
      FAIL("prepare accepted spacing 1e308");
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      CHECK_THAT(m, Contains("spacing [1e+308, 1e+308, 1e+308]") && Contains("bounds overflow"));
      CHECK_THAT(m, !Contains("sphere light"));
    }
  }
  SECTION("spacing outside [1e-100, 1e100]") {
    tessera::SceneDesc s = ball_scene();
    for (const double h : {1e-320, 1e-101, 1e101}) {
      s.geometry.spacing = Vec3(0.1, h, 0.1);
      INFO("spacing " << h);
      CHECK_THROWS_WITH(tessera::prepare(view, s), Contains("volume spacing") && Contains("[1e-100, 1e100]"));
    }
  }
  SECTION("camera position 1e308 is a position fault, not 'up is parallel'") {
    tessera::SceneDesc s = ball_scene();
    s.camera.position = Vec3(1e308, 1.0, 1.0);
    try {
      (void)tessera::prepare(view, s);
      FAIL("prepare accepted camera position 1e308");
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      CHECK_THAT(m, Contains("camera.position [1e+308, 1, 1]"));
      CHECK_THAT(m, !Contains("parallel"));
    }
    // The Camera alone (no prepare) says the distance overflows
    CHECK_THROWS_WITH(tessera::Camera(s.camera, 4, 4), Contains("overflows") && !Contains("parallel"));
  }
  SECTION("origin, look_at, aperture, focus distance beyond 2^40 spacings") {
    tessera::SceneDesc s = ball_scene();
    s.geometry.origin = Vec3(1e308, 0.0, 0.0);
    CHECK_THROWS_WITH(tessera::prepare(view, s), Contains("volume origin [1e+308, 0, 0]"));
    s = ball_scene();
    s.camera.look_at = Vec3(0.0, -1e13, 0.0);
    CHECK_THROWS_WITH(tessera::prepare(view, s), Contains("camera.look_at"));
    s = ball_scene();
    s.camera.aperture = 1e300;
    CHECK_THROWS_WITH(tessera::prepare(view, s), Contains("camera.aperture 1e+300"));
    s = ball_scene();
    s.camera.focus_distance = 1e300;
    CHECK_THROWS_WITH(tessera::prepare(view, s), Contains("camera.focus_distance 1e+300"));
  }
  SECTION("build_scene: a resolved point that overflows names its key") {
    tessera::config::RenderSpec spec;
    spec.name = "r";
    spec.transfer_function.opacity = {{0.0, 0.0}, {1.0, 1.0}};
    spec.camera.position.kind = tessera::config::PointSpec::Kind::Orbit;
    spec.camera.position.orbit.distance = 1e300;
    const tessera::Bounds b{Vec3(0.0), Vec3(1e10)};
    tessera::VolumeGeometry g;
    CHECK_THROWS_WITH(tessera::config::build_scene(spec, b, {0.0, 1.0}, g, nullptr),
                      Contains("camera.position is not finite after resolving"));
    const tessera::Bounds huge{Vec3(0.0), Vec3(1e308, 1e308, 1e308)};
    g.spacing = Vec3(1e307);
    spec.camera.position.orbit.distance = 2.0;
    CHECK_THROWS_WITH(tessera::config::build_scene(spec, huge, {0.0, 1.0}, g, nullptr),
                      Contains("volume.spacing") && Contains("bounds overflow"));
    // A light far out is named by its index in `lights`, whatever its type
    g.spacing = Vec3(0.1);
    tessera::config::RectLightSpec rect;
    rect.position = tessera::config::PointSpec::absolute(Vec3(0.0, 0.0, 5.0));
    tessera::config::SphereLightSpec sphere;
    sphere.position = tessera::config::PointSpec::absolute(Vec3(1e200, 3.0, 3.0));
    spec.lights = {rect, sphere};
    CHECK_THROWS_WITH(tessera::config::build_scene(spec, b, {0.0, 1.0}, g, nullptr),
                      Contains("lights[1].position [1e+200, 3, 3] lies beyond 2^40 smallest spacings"));
  }
}

TEST_CASE("tiny lights: no sample is discarded", "[robustness][scene]") {
  // A light whose solid-angle pdf squares past the double range used to make the power
  // heuristic inf / inf = NaN: about 6% of the samples of this scene were dropped.
  const std::vector<float> v = ball_field();
  const auto view = ball_view(v);
  for (const double size : {1e-9, 1e-100, 1e-200, 1e-300}) {
    tessera::SceneDesc s = ball_scene();
    tessera::nth_light<tessera::SphereLightDesc>(s.lights, 0).radius = size;
    s.lights.push_back(tessera::RectLightDesc{Vec3(0.75, 0.75, 3.0), Vec3(0.75), size, size, Color(5.0)});
    const TimedRender r = timed_render(view, s);
    INFO("light size " << size);
    CHECK(film_finite(r.film));
    CHECK(r.stats.discarded_samples == 0);
    CHECK(tessera::render_warnings(r.stats).empty());
  }
}

TEST_CASE("render_warnings: discarded fraction above 1e-3 and stalled paths", "[robustness][scene]") {
  tessera::RenderStats st;
  CHECK(tessera::render_warnings(st).empty());  // no samples at all
  st.samples = 10000;
  st.discarded_samples = 10;  // exactly 1e-3: not above
  CHECK(tessera::render_warnings(st).empty());
  st.discarded_samples = 11;
  std::vector<std::string> w = tessera::render_warnings(st);
  REQUIRE(w.size() == 1);
  CHECK_THAT(w[0], Contains("11 of 10000 samples") && Contains("discarded"));
  st.stalled_paths = 3;
  w = tessera::render_warnings(st);
  REQUIRE(w.size() == 2);
  CHECK_THAT(w[1], Contains("3 paths") && Contains("loop guard"));
  st.discarded_samples = 0;
  CHECK(tessera::render_warnings(st).size() == 1);
}

TEST_CASE("threads: the statistic is the number of threads actually used", "[robustness][scene]") {
  const std::vector<float> v = ball_field();
  const auto view = ball_view(v);
  tessera::SceneDesc s = ball_scene();
  const int cap = static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  s.options.threads = 65536;
  const TimedRender many = timed_render(view, s);
  CHECK(many.stats.threads == cap);
  s.options.threads = 1;
  const TimedRender one = timed_render(view, s);
  CHECK(one.stats.threads == 1);
  // The image does not depend on the thread count
  for (std::size_t i = 0; i < one.film.pixels().size(); ++i) {
    CHECK(one.film.pixels()[i].r == many.film.pixels()[i].r);
    if (one.film.pixels()[i].r != many.film.pixels()[i].r) break;
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    s.options.threads = 8;
    CHECK(timed_render(view, s).stats.threads == 1);
  }
}

TEST_CASE("tessera-render: every numeric key at its extremes finishes or fails naming it", "[robustness][scene][cli]") {
  struct Case {
    const char* what;
    std::map<std::string, std::string> subst;
    const char* error;  ///< nullptr: renders (exit 0) with a finite image
    const char* not_in_error = nullptr;
    const char* warning = nullptr;  ///< renders with this warning (scene_warnings.h); nullptr: none
  };
  const std::vector<Case> cases = {
      {"spacing 1e308", {{"SPACING", "[1e308, 1e308, 1e308]"}}, "volume.spacing", "sphere light"},
      {"spacing 1e-320", {{"SPACING", "[1e-320, 1e-320, 1e-320]"}}, "volume.spacing"},
      // A volume 1.5e-89 wide has optical depth ~1e-87: correctly shows nothing, and says why
      {"spacing 1e-90",
       {{"SPACING", "[1e-90, 1e-90, 1e-90]"}},
       nullptr,
       nullptr,
       "likely cause: transfer_function.density_scale too small"},
      {"spacing 1e90", {{"SPACING", "[1e90, 1e90, 1e90]"}}, nullptr},
      {"anisotropic spacing 1e-12", {{"SPACING", "[1e-12, 1, 1]"}}, "volume.spacing: with dims 16x16x16"},
      {"origin 1e308", {{"ORIGIN", "[1e308, 0, 0]"}}, "volume.origin"},
      {"origin 1e7", {{"ORIGIN", "[1e7, -1e7, 1e7]"}}, nullptr},
      {"camera position 1e308", {{"CAMPOS", "[1e308, 1, 1]"}}, "camera.position", "parallel"},
      {"camera orbit distance 1e300",
       {{"CAMPOS", "{orbit: {azimuth: 0, elevation: 0, distance: 1e300}}"}},
       "camera.position"},
      {"fov 1e-300", {{"FOV", "1e-300"}}, nullptr},
      // The ball covers ~1e-5 of a pixel: correctly shows nothing, and says why
      {"fov 179.9999", {{"FOV", "179.9999"}}, nullptr, nullptr, "cover less than one pixel"},
      {"aperture 1e300", {{"APERTURE", "1e300"}}, "camera.aperture"},
      {"aperture 10", {{"APERTURE", "10"}}, nullptr},
      {"light intensity 1e308",
       {{"LIGHT", "{type: sphere, position: [3, 3, 3], radius: 1, intensity: 1e308}"}},
       "lights[0].intensity 1e+308"},
      {"light intensity 1e29", {{"LIGHT", "{type: sphere, position: [3, 3, 3], radius: 1, intensity: 1e29}"}}, nullptr},
      {"light intensity times color overflows",
       {{"LIGHT", "{type: sphere, position: [3, 3, 3], radius: 1, color: [10, 1, 1], intensity: 1e308}"}},
       "lights[0].intensity"},
      {"light radius 1e-300",
       {{"LIGHT", "{type: sphere, position: [3, 3, 3], radius: 1e-300, intensity: 1}"}},
       nullptr},
      {"light radius 1e300",
       {{"LIGHT", "{type: sphere, position: [3, 3, 3], radius: 1e300, intensity: 1}"}},
       "lights[0].radius 1e+300"},
      {"rect size 1e-200",
       {{"LIGHT", "{type: rect, position: [3, 3, 3], target: center, size: 1e-200, intensity: 1}"}},
       nullptr},
      {"max_bounces 1000000", {{"BOUNCES", "1000000"}}, nullptr},
  };
  for (const Case& c : cases) {
    TempDir dir;
    write_ball_config(dir, c.subst);
    const CliRun r = run_render_cli(dir, "scene.yaml --quiet --stats stats.json");
    INFO(c.what << ": exit " << r.status << " after " << r.seconds << " s; stderr: " << r.err);
    CHECK(r.seconds < kBoundSeconds);
    if (c.error) {
      CHECK(r.status == 1);
      CHECK_THAT(r.err, Contains(c.error));
      if (c.not_in_error) CHECK_THAT(r.err, !Contains(c.not_in_error));
    } else {
      REQUIRE(r.status == 0);
      CHECK(image_finite(tessera::read_exr(dir.file("out/r.exr"))));
      const std::string json = slurp(dir.file("stats.json"));
      CHECK_THAT(json, Contains("\"discarded_samples\": 0"));
      if (c.warning) CHECK_THAT(r.err, Contains(c.warning));
      else CHECK_THAT(json, Contains("\"warnings\": []"));
    }
  }
}

TEST_CASE("tessera-render: threads stat and warnings in --stats", "[robustness][scene][cli]") {
  TempDir dir;
  write_ball_config(dir, {});
  const CliRun r = run_render_cli(dir, "scene.yaml --quiet --threads 65536 --stats stats.json");
  REQUIRE(r.status == 0);
  const std::string json = slurp(dir.file("stats.json"));
  const int cap = static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  CHECK_THAT(json, Contains("\"threads\": " + std::to_string(cap) + ","));
  CHECK_THAT(json, !Contains("65536"));
  CHECK_THAT(json, Contains("\"stalled_paths\": 0"));
  CHECK_THAT(json, Contains("\"warnings\": []"));
  CHECK(r.err.empty());
  // A render whose paths stall warns on stderr and in the JSON, and still succeeds
  TempDir far;
  write_ball_config(far, {{"CAMPOS", "[1e11, 0.75, 0.75]"}, {"FOV", "5e-10"}, {"DENS", "1e308"}, {"OPAC", "1"}});
  std::string text = slurp(far.file("scene.yaml"));
  text.replace(text.find("[[0.0, 0.0], [0.5, 0.0]"), 23, "[[0.0, 1.0], [0.5, 1.0]");
  far.write("scene.yaml", text);
  const CliRun s = run_render_cli(far, "scene.yaml --quiet --stats stats.json");
  INFO(s.err);
  REQUIRE(s.status == 0);
  CHECK_THAT(s.err, Contains("tessera-render: warning: r: ") && Contains("loop guard"));
  const std::string sj = slurp(far.file("stats.json"));
  CHECK_THAT(sj, Contains("\"warnings\": [\"r: ") && Contains("\"warnings\": [\""));
  CHECK_THAT(sj, !Contains("\"stalled_paths\": 0"));
}
