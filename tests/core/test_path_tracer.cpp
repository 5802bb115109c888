// Tests of the estimator's structure (docs/physics.md "The estimator"): single scattering is
// exactly the path tracer with one real collision; it loses the multiply-scattered energy in a furnace;
// and next-event estimation to area lights, MIS-weighted against phase / BRDF sampling, keeps
// a furnace enclosed by rect lights at the lights' radiance.
//
// Statistics: z-tests with |z| < 4 (two-sided, false alarm 6.3e-5 per check), standard errors
// from the per-pixel sample variance. Fixed seeds.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "test_support.h"

#include <cstring>
#include <string>
#include <vector>

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

namespace {

constexpr double kL = 0.7;

/// Unit box of n^3 vertices, albedo 1, phase shading, multiple scattering, no lights.
tessera::SceneDesc scattering_box(int n, double tau) {
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (n - 1));
  s.tf.density_scale = tau;
  s.tf.opacity = tessera::ScalarTF::constant(1.0);
  s.tf.diffuse = tessera::ColorTF::constant(Color(1.0));
  s.camera.position = Vec3(0.5, 0.5, -0.7);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 50.0;
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 100000;
  s.integrator.shading = tessera::Shading::Phase;
  s.integrator.phase_g = 0.3;
  s.integrator.macrocell = 4;
  s.image = {16, 16, 64, 0.0};
  s.options.seed = 31;
  return s;
}

/// Six inward-facing 3 x 3 rect lights of radiance L enclosing [-1, 2]^3 (the box and the
/// camera inside): every direction from inside meets exactly one front face.
void enclose_in_rect_lights(tessera::SceneDesc& s) {
  const Vec3 c(0.5);
  for (int axis = 0; axis < 3; ++axis)
    for (const double side : {-1.0, 2.0}) {
      Vec3 p = c;
      p[axis] = side;
      s.lights.push_back(tessera::RectLightDesc{p, c, 3.0, 3.0, Color(kL)});
    }
  s.background.color = Color(0.0);
}

}  // namespace

TEST_CASE("single scattering equals multiple scattering with max_bounces 1, bit for bit", "[path_tracer][render]") {
  constexpr int n = 14;
  const std::vector<float> field = tessera_test::blobby_field(n, n, n);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
  tessera::SceneDesc s = scattering_box(n, 10.0);
  s.tf.opacity = tessera::ScalarTF({0.0, 0.2, 1.0}, {0.0, 0.5, 1.0});
  s.tf.specular = tessera::ColorTF::constant(Color(0.2));
  s.tf.emission = tessera::ColorTF({0.5, 1.0}, {Color(0.0), Color(1.0)});
  s.integrator.shading = tessera::Shading::Hybrid;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 1.8, 0.5), Vec3(0.5, 0.0, 0.5), 1.0, 1.0, Color(3.0)});
  s.lights.push_back(tessera::SphereLightDesc{Vec3(-1.0, 0.5, 0.0), 0.3, Color(4.0)});
  s.background.type = tessera::BackgroundType::Gradient;
  s.image.spp = 4;

  tessera::SceneDesc single = s, one = s;
  single.integrator.scattering = tessera::Scattering::Single;
  single.integrator.max_bounces = 50;  // ignored by single scattering
  one.integrator.scattering = tessera::Scattering::Multiple;
  one.integrator.max_bounces = 1;
  tessera::RenderStats st_single, st_one, st_multi;
  const tessera::Image a = tessera_test::render_film(tessera::prepare(view, single), &st_single).resolve();
  const tessera::Image b = tessera_test::render_film(tessera::prepare(view, one), &st_one).resolve();
  tessera_test::render_film(tessera::prepare(view, s), &st_multi);
  CHECK(std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0);
  CHECK(st_single.real_collisions == st_one.real_collisions);
  // Single scattering has at most one real collision per camera sample; multiple has more.
  CHECK(st_single.real_collisions <= st_single.samples);
  CHECK(st_multi.real_collisions > st_single.real_collisions);
}

TEST_CASE("single scattering in a furnace loses the multiply scattered energy", "[path_tracer][render]") {
  constexpr int n = 5;
  const std::vector<float> field = tessera_test::constant_field(n, n, n, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
  tessera::SceneDesc s = scattering_box(n, 5.0);
  s.background.color = Color(kL);
  s.integrator.scattering = tessera::Scattering::Single;
  const auto single = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(view, s)));
  s.integrator.scattering = tessera::Scattering::Multiple;
  const auto multi = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(view, s)));
  INFO("single " << single.mean << " +- " << single.se << ", multiple " << multi.mean << " +- " << multi.se);
  CHECK(multi.z(kL) < 4.0);
  CHECK(kL - single.mean > 4.0 * single.se);  // significantly darker than the furnace value
}

TEST_CASE("furnace enclosed by rect lights: NEE + MIS to area lights keeps radiance L", "[path_tracer][render]") {
  // No background: all light comes from six inward-facing rect lights of radiance L that
  // enclose the camera and the medium, so every pixel's expected value is L.
  SECTION("homogeneous, phase") {
    constexpr int n = 5;
    const std::vector<float> field = tessera_test::constant_field(n, n, n, 1.0f);
    const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
    for (const double tau : {1.0, 6.0}) {
      tessera::SceneDesc s = scattering_box(n, tau);
      enclose_in_rect_lights(s);
      for (const auto shadow : {tessera::ShadowMode::Ratio, tessera::ShadowMode::Delta}) {
        s.integrator.shadow = shadow;
        tessera::RenderStats st;
        const auto L = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(view, s), &st));
        INFO("tau " << tau << " shadow " << static_cast<int>(shadow) << ": " << L.mean << " +- " << L.se);
        CHECK(st.real_collisions > 0);
        CHECK(L.z(kL) < 4.0);
      }
    }
  }
  SECTION("heterogeneous, hybrid Lambert surfaces") {
    constexpr int n = 17;
    const std::vector<float> field = tessera_test::blobby_field(n, n, n);
    const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
    tessera::SceneDesc s = scattering_box(n, 15.0);
    s.tf.opacity = tessera::ScalarTF({0.0, 0.1, 0.6}, {0.0, 0.3, 1.0});
    s.integrator.shading = tessera::Shading::Hybrid;
    s.integrator.gradient_factor = 4.0;
    enclose_in_rect_lights(s);
    tessera::RenderStats st;
    const auto L = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(view, s), &st));
    INFO(L.mean << " +- " << L.se);
    CHECK(st.gradient_lookups > 0);
    CHECK(L.z(kL) < 4.0);
  }
}
