// White-furnace tests of the multiple-scattering estimator (docs/physics.md "The
// estimator"): a medium that scatters without absorbing (albedo 1) under a constant background of radiance L and no
// other light leaves every pixel's expected radiance exactly L, whatever the density, the
// phase asymmetry or the majorant layout. Lambertian surface events (no specular) conserve
// energy too, so the furnace also holds in brdf and hybrid shading.
//
// Statistics: image mean vs L, two-sided z-test with |z| < 4 (false-alarm probability
// 6.3e-5 per check), standard error from the per-pixel sample variance. Fixed seeds.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "test_support.h"

#include <cmath>
#include <memory>
#include <string>
#include <vector>

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

namespace {

constexpr double kL = 0.7;

/// Unit box [0,1]^3 of n^3 vertices seen by a camera that frames it with a margin, so some
/// pixels see the bare background; albedo 1, background L, no lights.
tessera::SceneDesc furnace_scene(int n, double tau, double g, int spp) {
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (n - 1));
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = tau;  // optical thickness across the box at opacity 1
  s.tf.opacity = tessera::ScalarTF::constant(1.0);
  s.tf.diffuse = tessera::ColorTF::constant(Color(1.0));
  s.camera.position = Vec3(1.3, 0.8, -2.2);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 32.0;
  s.background.color = Color(kL);
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 100000;
  s.integrator.shading = tessera::Shading::Phase;
  s.integrator.phase_g = g;
  s.integrator.macrocell = 2;
  s.image = {16, 16, spp, 0.0};
  s.options.seed = 77;
  return s;
}

void check_furnace(const FieldView& view, const tessera::SceneDesc& s, const std::string& what) {
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  tessera::RenderStats st;
  const tessera::Film film = tessera_test::render_film(ps, &st);
  const auto L = tessera_test::luminance_stats(film);
  const double red = tessera_test::mean_red(film);
  INFO(what << ": mean " << L.mean << " +- " << L.se << " (z " << L.z(kL) << "), red " << red << ", real collisions "
            << st.real_collisions);
  CHECK(st.real_collisions > 0);
  CHECK(st.discarded_samples == 0);
  CHECK(L.z(kL) < 4.0);
  CHECK(std::fabs(red - kL) < 4.0 * L.se + 1e-12);
}

}  // namespace

TEST_CASE("white furnace: homogeneous box, phase shading, multiple scattering", "[furnace][render]") {
  constexpr int n = 5;
  const std::vector<float> field = tessera_test::constant_field(n, n, n, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
  for (const double tau : {0.5, 5.0, 20.0}) {
    for (const double g : {-0.7, 0.0, 0.7}) {
      const int spp = tau > 10.0 ? 64 : 128;
      tessera::SceneDesc s = furnace_scene(n, tau, g, spp);
      check_furnace(view, s, "tau " + std::to_string(tau) + ", g " + std::to_string(g));
    }
  }
}

TEST_CASE("white furnace: majorant mode and shadow estimator do not matter", "[furnace][render]") {
  constexpr int n = 5;
  const std::vector<float> field = tessera_test::constant_field(n, n, n, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
  tessera::SceneDesc s = furnace_scene(n, 5.0, 0.3, 128);
  SECTION("global majorant") {
    s.integrator.majorant = tessera::MajorantMode::Global;
    check_furnace(view, s, "global majorant");
  }
  SECTION("delta-tracked shadow rays") {
    s.integrator.shadow = tessera::ShadowMode::Delta;
    check_furnace(view, s, "delta shadow");
  }
  SECTION("ratio tracking without roulette") {
    s.integrator.shadow_roulette = false;
    check_furnace(view, s, "no shadow roulette");
  }
  SECTION("majorant far above sigma_t (opacity 1 only at one vertex)") {
    // A field that is 1 at one corner vertex and 0.2 elsewhere, opacity = u: the global
    // majorant is 5x the extinction almost everywhere, so most collisions are null.
    std::vector<float> f = tessera_test::constant_field(n, n, n, 0.2f);
    f[0] = 1.0f;
    const FieldView v = FieldView::contiguous(f.data(), tessera::DType::Float32, n, n, n);
    s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
    s.tf.density_scale = 20.0;
    s.integrator.majorant = tessera::MajorantMode::Global;
    check_furnace(v, s, "loose majorant");
  }
}

TEST_CASE("white furnace: heterogeneous field in phase, brdf and hybrid shading", "[furnace][render]") {
  // Lambert-only surface events (specular TF absent): albedo 1 reflects all energy into the
  // hemisphere around the normal, so the furnace holds for every shading mode.
  constexpr int n = 17;
  const std::vector<float> field = tessera_test::blobby_field(n, n, n);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
  tessera::SceneDesc s = furnace_scene(n, 12.0, 0.4, 96);
  s.tf.opacity = tessera::ScalarTF({0.0, 0.1, 0.6, 1.0}, {0.0, 0.2, 1.0, 1.0});
  s.integrator.macrocell = 4;
  for (const auto shading : {tessera::Shading::Phase, tessera::Shading::Brdf, tessera::Shading::Hybrid}) {
    s.integrator.shading = shading;
    s.integrator.gradient_factor = 3.0;
    check_furnace(view, s,
                  shading == tessera::Shading::Phase  ? "phase"
                  : shading == tessera::Shading::Brdf ? "brdf"
                                                      : "hybrid");
  }
}

TEST_CASE("white furnace under a constant envmap: envmap importance sampling in the loop", "[furnace][render]") {
  // An equirectangular map whose texels all hold L is the constant background in disguise;
  // its sampling density ~ sin(theta) exercises the envmap pdf in NEE and MIS.
  constexpr int n = 5;
  const std::vector<float> field = tessera_test::constant_field(n, n, n, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
  auto env = std::make_shared<tessera::Image>();
  env->width = 16;
  env->height = 8;
  env->rgba.assign(16 * 8 * 4, static_cast<float>(kL));
  tessera::SceneDesc s = furnace_scene(n, 5.0, 0.5, 128);
  s.background.type = tessera::BackgroundType::EnvMap;
  s.background.envmap = env;
  s.background.up = Vec3(0.2, 1.0, 0.1);
  check_furnace(view, s, "envmap");
}
