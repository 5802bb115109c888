// Tests for render() / render_tiles() robustness and bookkeeping: NaN voxels never produce
// NaN pixels or discarded samples and are counted; a scene whose opacity is zero everywhere
// samples no free paths and shows the background exactly; lights are transparent emitters;
// invalid calls throw naming the fault.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "light_lookup.h"
#include "test_support.h"

#include <cmath>
#include <limits>
#include <vector>

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

namespace {

constexpr int N = 16;

tessera::SceneDesc lit_scene() {
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (N - 1));
  s.tf.density_scale = 20.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.2, 1.0}, {0.0, 0.5, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.8, 0.7, 0.6));
  s.tf.specular = tessera::ColorTF::constant(Color(0.1));
  s.tf.emission = tessera::ColorTF({0.0, 1.0}, {Color(0.0), Color(0.5)});
  s.camera.position = Vec3(0.5, 0.5, -2.0);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 35.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 2.0, 0.5), Vec3(0.5, 0.0, 0.5), 1.0, 1.0, Color(4.0)});
  s.lights.push_back(tessera::SphereLightDesc{Vec3(2.0, 0.5, 0.0), 0.3, Color(5.0)});
  s.background.type = tessera::BackgroundType::Gradient;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.image = {16, 16, 8, 0.0};
  s.options.seed = 5;
  return s;
}

bool all_finite(const tessera::Image& img) {
  for (const float v : img.rgba)
    if (!std::isfinite(v)) return false;
  for (const float v : img.variance)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace

TEST_CASE("NaN voxels: finite pixels, nothing discarded, NaN vertices counted", "[render]") {
  std::vector<float> field = tessera_test::blobby_field(N, N, N);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::uint64_t nans = 0;
  for (std::size_t i = 0; i < field.size(); i += 7) {
    field[i] = nan;  // every 7th vertex, spread through the dense shell as well
    ++nans;
  }
  field[5] = inf;
  field[6] = -inf;
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, N, N, N);
  for (const auto sc : {tessera::Scattering::Single, tessera::Scattering::Multiple}) {
    for (const auto shading : {tessera::Shading::Phase, tessera::Shading::Brdf, tessera::Shading::Hybrid}) {
      tessera::SceneDesc s = lit_scene();
      s.integrator.scattering = sc;
      s.integrator.shading = shading;
      const tessera::PreparedScene ps = tessera::prepare(view, s);
      tessera::RenderStats st;
      const tessera::Film film = tessera_test::render_film(ps, &st);
      const tessera::Image img = film.resolve();
      INFO("scattering " << static_cast<int>(sc) << " shading " << static_cast<int>(shading));
      CHECK(all_finite(img));
      CHECK(st.discarded_samples == 0);
      CHECK(st.real_collisions > 0);
      CHECK(st.samples == static_cast<std::uint64_t>(16 * 16 * 8));
      CHECK(st.nan_voxels_seen == nans);
    }
  }
}

TEST_CASE("all-zero opacity: no free-flight lookups, the background exactly, alpha 0", "[render]") {
  const std::vector<float> field = tessera_test::blobby_field(N, N, N);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, N, N, N);
  tessera::SceneDesc s = lit_scene();
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 0.0});
  s.lights.clear();
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(0.25, 0.5, 0.75);
  for (const auto mode : {tessera::MajorantMode::Grid, tessera::MajorantMode::Global}) {
    for (const auto fp : {tessera::FreePath::Delta, tessera::FreePath::Raymarch}) {
      s.integrator.majorant = mode;
      s.integrator.free_path = fp;
      s.integrator.scattering = tessera::Scattering::Multiple;
      const tessera::PreparedScene ps = tessera::prepare(view, s);
      tessera::RenderStats st;
      const tessera::Image img = tessera_test::render_film(ps, &st).resolve();
      CHECK(st.free_flight_lookups == 0);
      CHECK(st.density_lookups() == 0);
      CHECK(st.real_collisions == 0);
      bool exact = true;
      for (int i = 0; i < img.width * img.height; ++i)
        exact = exact && img.rgba[4 * i] == 0.25f && img.rgba[4 * i + 1] == 0.5f && img.rgba[4 * i + 2] == 0.75f &&
                img.rgba[4 * i + 3] == 0.0f;
      CHECK(exact);
    }
  }
}

TEST_CASE("lights are transparent, one-sided emitters seen directly by the camera", "[render]") {
  // No medium at all (zero density): the camera sees a rect light, and behind it the
  // background; the rect's back side shows only the background.
  const std::vector<float> field = tessera_test::constant_field(2, 2, 2, 0.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 2, 2, 2);
  tessera::SceneDesc s;
  s.tf.density_scale = 0.0;
  s.camera.position = Vec3(0.0, 0.0, 5.0);
  s.camera.look_at = Vec3(0.0);
  s.camera.fov_deg = 5.0;
  s.background.color = Color(0.1);
  s.image = {4, 4, 4, 0.0};
  // Facing the camera: radiance 2 + background 0.1 on every pixel (the rect fills the view)
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.0), Vec3(0.0, 0.0, 1.0), 10.0, 10.0, Color(2.0)});
  {
    const tessera::PreparedScene ps = tessera::prepare(view, s);
    const tessera::Image img = tessera_test::render_film(ps).resolve();
    CHECK(img.rgba[0] == Approx(2.1).epsilon(1e-6));
    CHECK(img.rgba[4 * 15 + 2] == Approx(2.1).epsilon(1e-6));
  }
  // Facing away: only the background
  tessera::nth_light<tessera::RectLightDesc>(s.lights, 0).target = Vec3(0.0, 0.0, -1.0);
  {
    const tessera::PreparedScene ps = tessera::prepare(view, s);
    const tessera::Image img = tessera_test::render_film(ps).resolve();
    CHECK(img.rgba[0] == Approx(0.1).epsilon(1e-6));
  }
  // A hidden background still contributes nothing to camera rays
  s.background.visible = false;
  {
    const tessera::PreparedScene ps = tessera::prepare(view, s);
    const tessera::Image img = tessera_test::render_film(ps).resolve();
    CHECK(img.rgba[0] == 0.0f);
  }
}

TEST_CASE("render_tiles rejects a film of the wrong size and unknown tile indices", "[render]") {
  const std::vector<float> field = tessera_test::constant_field(3, 3, 3, 0.5f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 3, 3, 3);
  tessera::SceneDesc s;
  s.image = {8, 6, 1, 0.0};
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  tessera::RenderStats st;
  tessera::Film wrong(6, 8);
  CHECK_THROWS_WITH(tessera::render(ps, wrong, st), Catch::Contains("6x8") && Catch::Contains("8x6"));
  tessera::Film film(8, 6);
  const std::vector<int> bad = {0, static_cast<int>(ps.tiles().size())};
  CHECK_THROWS_WITH(tessera::render_tiles(ps, bad, film, st), Catch::Contains("tile index"));
}

TEST_CASE("prepare rejects invalid scenes naming the fault", "[render]") {
  const std::vector<float> field = tessera_test::constant_field(3, 3, 3, 0.5f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 3, 3, 3);
  tessera::SceneDesc s;
  s.image = {8, 8, 1, 0.0};
  REQUIRE_NOTHROW(tessera::prepare(view, s));
  SECTION("tf range") {
    s.tf.lo = 1.0;
    s.tf.hi = 1.0;
    CHECK_THROWS_WITH(tessera::prepare(view, s), Catch::Contains("lo < hi"));
  }
  SECTION("spacing") {
    s.geometry.spacing = Vec3(1.0, 0.0, 1.0);
    CHECK_THROWS_WITH(tessera::prepare(view, s), Catch::Contains("spacing"));
  }
  SECTION("phase g") {
    s.integrator.phase_g = 1.0;
    CHECK_THROWS_WITH(tessera::prepare(view, s), Catch::Contains("phase_g"));
  }
  SECTION("negative opacity") {
    s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.5, -0.1});
    CHECK_THROWS_WITH(tessera::prepare(view, s), Catch::Contains("opacity"));
  }
  SECTION("camera") {
    s.camera.up = Vec3(0.0, 0.0, 1.0);  // default camera looks along -z
    CHECK_THROWS_WITH(tessera::prepare(view, s), Catch::Contains("parallel"));
  }
  SECTION("rect light size") {
    s.lights.push_back(tessera::RectLightDesc{Vec3(0.0), Vec3(0.0, 0.0, 1.0), 0.0, 1.0, Color(1.0)});
    CHECK_THROWS_WITH(tessera::prepare(view, s), Catch::Contains("rect light"));
  }
}
