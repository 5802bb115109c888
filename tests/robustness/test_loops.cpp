// Every loop advances or stops (docs/physics.md "Loop guards and scene bounds"): the known
// reproducers that used to hang (density_scale or opacity 1e308, raymarch step 1e-300, a light
// at 1e200) render or fail within a bounded time; extinction is clamped, not scaled; a step
// that no longer advances t ends its path and is counted in stalled_paths.
#include <tessera/image_io.h>
#include <tessera/loop_bounds.h>
#include <tessera/render.h>

#include "light_lookup.h"
#include "loop_support.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

using Catch::Matchers::Contains;
using tessera::Color;
using tessera::Vec3;
using namespace tessera_test;

namespace {

/// Generous bound for "finishes rather than hangs" (16x16 at 4 spp).
constexpr double kBoundSeconds = 20.0;

bool bit_identical(const tessera::Film& a, const tessera::Film& b) {
  const auto &pa = a.pixels(), &pb = b.pixels();
  if (pa.size() != pb.size()) return false;
  for (std::size_t i = 0; i < pa.size(); ++i)
    if (pa[i].r != pb[i].r || pa[i].g != pb[i].g || pa[i].b != pb[i].b || pa[i].a != pb[i].a) return false;
  return true;
}

}  // namespace

TEST_CASE("density_scale and opacity up to 1e308 render in bounded time", "[robustness][loops]") {
  const std::vector<float> v = ball_field();
  const auto view = ball_view(v);
  for (const double dens : {1e4, 1e10, 1e100, 1e308}) {
    for (const double opac : {0.5, 1e10, 1e308}) {
      tessera::SceneDesc s = ball_scene();
      s.tf.density_scale = dens;
      s.tf.opacity = tessera::ScalarTF({0.0, 0.5, 0.7, 1.0}, {0.0, 0.0, opac, 1.0});
      for (const auto shadow : {tessera::ShadowMode::Ratio, tessera::ShadowMode::Delta}) {
        s.integrator.shadow = shadow;
        const TimedRender r = timed_render(view, s);
        INFO("density_scale " << dens << ", opacity " << opac << ": " << r.seconds << " s");
        CHECK(r.seconds < kBoundSeconds);
        CHECK(film_finite(r.film));
        CHECK(r.stats.discarded_samples == 0);
        CHECK(r.stats.stalled_paths == 0);
        CHECK(r.stats.real_collisions > 0);
      }
    }
  }
}

TEST_CASE("extinction beyond 1000 per voxel is clamped: an opaque medium's image is unchanged", "[robustness][loops]") {
  // Constant opacity 1: every density at or above the clamp is the same medium, bit for bit
  const std::vector<float> v = ball_field();
  const auto view = ball_view(v);
  tessera::SceneDesc s = ball_scene();
  s.tf.opacity = tessera::ScalarTF::constant(1.0);
  const double cap = tessera::kMaxOpticalThicknessPerVoxel / s.geometry.spacing.x;  // 1e4 / world unit
  s.tf.density_scale = cap;
  const TimedRender at_cap = timed_render(view, s);
  s.tf.density_scale = 1e308;
  const TimedRender huge = timed_render(view, s);
  CHECK(bit_identical(at_cap.film, huge.film));
  CHECK(at_cap.stats.free_flight_lookups == huge.stats.free_flight_lookups);
  // Below the clamp nothing changes: half the cap is a different (still opaque) medium
  s.tf.density_scale = 0.5 * cap;
  const TimedRender half = timed_render(view, s);
  CHECK(!bit_identical(at_cap.film, half.film));
}

TEST_CASE("raymarch step: below extent / 2^20 refused naming the minimum, at it bounded", "[robustness][loops]") {
  const std::vector<float> v = ball_field();
  const auto view = ball_view(v);
  tessera::SceneDesc s = ball_scene();
  s.integrator.free_path = tessera::FreePath::Raymarch;
  for (const double step : {1e-300, 1e-9}) {
    s.integrator.step = step;
    INFO("step " << step);
    CHECK_THROWS_WITH(tessera::prepare(view, s),
                      Contains("integrator.step") && Contains("below the minimum") && Contains("2^20"));
  }
  // The minimum for a 16^3 box: its diagonal, 15 sqrt(3) spacings, over 2^20
  const double min_step = 15.0 * std::sqrt(3.0) / tessera::kMaxMarchSteps;
  s.integrator.step = min_step * 1.0001;
  s.image = {4, 4, 1, 0.0};
  const TimedRender r = timed_render(view, s);
  CHECK(r.seconds < kBoundSeconds);
  CHECK(film_finite(r.film));
  CHECK(r.stats.stalled_paths == 0);
}

TEST_CASE("lights far from the data are refused naming the light and key", "[robustness][loops]") {
  const std::vector<float> v = ball_field();
  const auto view = ball_view(v);
  SECTION("sphere light at [1e200, 3, 3]") {
    tessera::SceneDesc s = ball_scene();
    tessera::nth_light<tessera::SphereLightDesc>(s.lights, 0).center = Vec3(1e200, 3.0, 3.0);
    CHECK_THROWS_WITH(tessera::prepare(view, s), Contains("sphere light 0: position") && Contains("1e+200"));
  }
  SECTION("rect light target and size") {
    tessera::SceneDesc s = ball_scene();
    s.lights.push_back(tessera::RectLightDesc{Vec3(0.75, 0.75, 4.0), Vec3(0.75, 0.75, -1e200), 1.0, 1.0, Color(3.0)});
    CHECK_THROWS_WITH(tessera::prepare(view, s), Contains("rect light 0: target"));
    tessera::nth_light<tessera::RectLightDesc>(s.lights, 0).target = Vec3(0.75);
    tessera::nth_light<tessera::RectLightDesc>(s.lights, 0).width = 1e300;
    CHECK_THROWS_WITH(tessera::prepare(view, s), Contains("rect light 0: width") && Contains("1e+300"));
  }
  SECTION("just inside the bound: renders in bounded time") {
    tessera::SceneDesc s = ball_scene();
    tessera::nth_light<tessera::SphereLightDesc>(s.lights, 0).center = Vec3(1e10, 3.0, 3.0);
    tessera::nth_light<tessera::SphereLightDesc>(s.lights, 0).radius = 1e9;
    const TimedRender r = timed_render(view, s);
    CHECK(r.seconds < kBoundSeconds);
    CHECK(film_finite(r.film));
    CHECK(r.stats.discarded_samples == 0);
  }
}

TEST_CASE("a step that no longer advances t ends its path and is counted", "[robustness][loops]") {
  // The camera at 1e11 world units (just inside 2^40 spacings) looking at an opaque ball
  // through a 5e-10 degree field of view: near t = 1e11 a double resolves 1.5e-5, while a
  // free-flight step at the clamped extinction is 1e-5 on average, so some steps round to
  // nothing. The guard ends those paths (no hang), counts them and the image stays finite.
  const std::vector<float> v = ball_field();
  const auto view = ball_view(v);
  tessera::SceneDesc s = ball_scene();
  s.tf.opacity = tessera::ScalarTF::constant(1.0);
  s.tf.density_scale = 1e308;
  s.camera.position = Vec3(1e11, 0.75, 0.75);
  s.camera.fov_deg = 5e-10;
  const TimedRender r = timed_render(view, s);
  CHECK(r.seconds < kBoundSeconds);
  CHECK(film_finite(r.film));
  CHECK(r.stats.stalled_paths > 0);
  CHECK(r.stats.stalled_paths < r.stats.samples);
  const std::vector<std::string> w = tessera::render_warnings(r.stats);
  REQUIRE(w.size() == 1);
  CHECK_THAT(w[0], Contains(std::to_string(r.stats.stalled_paths) + " paths") && Contains("loop guard"));
  // The same scene from an ordinary distance stalls nothing
  s.camera.position = Vec3(4.0, 0.75, 0.75);
  s.camera.fov_deg = 35.0;
  CHECK(timed_render(view, s).stats.stalled_paths == 0);
}

TEST_CASE("tessera-render: the reproducers finish or fail within seconds", "[robustness][loops][cli]") {
  struct Case {
    const char* what;
    std::map<std::string, std::string> subst;
    const char* error;  ///< nullptr: renders (exit 0) with a finite image
  };
  const std::vector<Case> cases = {
      {"density_scale 1e308", {{"DENS", "1e308"}}, nullptr},
      {"density_scale 1e10", {{"DENS", "1e10"}}, nullptr},
      {"opacity 1e308", {{"OPAC", "1e308"}}, nullptr},
      {"raymarch step 1e-300", {{"FREEPATH", "raymarch"}, {"STEP", "1e-300"}}, "integrator.step 1e-300"},
      {"light at [1e200, 3, 3]",
       {{"LIGHT", "{type: sphere, position: [1e200, 3, 3], radius: 0.1, intensity: 1}"}},
       "lights[0].position [1e+200, 3, 3]"},
      {"rect light at [1e200, 3, 3]",
       {{"LIGHT", "{type: rect, position: [1e200, 3, 3], target: center, size: 1, intensity: 1}"}},
       "lights[0].position [1e+200, 3, 3]"},
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
    } else {
      REQUIRE(r.status == 0);
      CHECK(image_finite(tessera::read_exr(dir.file("out/r.exr"))));
      const std::string json = slurp(dir.file("stats.json"));
      CHECK_THAT(json, Contains("\"stalled_paths\": 0"));
    }
  }
}
