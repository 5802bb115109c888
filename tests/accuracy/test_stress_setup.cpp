// Stress: degenerate setups (docs/accuracy.md, "Stress").
//  - prepare() rejects, with std::invalid_argument naming the fault, an up vector parallel to
//    the view direction (exactly and to 1e-13), a zero up, zero-size rect lights (width or
//    height 0), zero-radius sphere lights, fov 0 / 180 and a transfer-function range whose
//    width hi - lo overflows.
//  - Opacity zero everywhere (and density_scale 0): the medium is never tracked
//    (free_flight_lookups == transmittance_lookups == real_collisions == 0, alpha 0) while
//    lights and the background still render: every pixel of a constant background without
//    lights is exactly that background (with and without tile culling); with lights, a
//    gradient background, a thin lens and multiple scattering the image does not depend on the
//    field at all: bit-identical to a zero field and to density_scale 0.
#include <catch2/catch.hpp>

#include <variant>

#include "accuracy_support.h"

#include <stdexcept>

using namespace tessera_acc;

namespace {

tessera::SceneDesc small_scene() {
  tessera::SceneDesc s = unit_box_scene(5.0, 0.8);
  s.background.color = Color(0.3);
  s.camera.position = Vec3(1.8, 1.2, -1.5);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.image = {8, 8, 4, 0.0};
  return s;
}

std::string prepare_error(const tessera::SceneDesc& s) {
  const std::vector<float> f = constant_field(3, 3, 3, 1.0f);
  const FieldView view = FieldView::contiguous(f.data(), tessera::DType::Float32, 3, 3, 3);
  try {
    tessera::prepare(view, s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("prepare() names degenerate cameras and lights", "[accuracy][stress]") {
  tessera::SceneDesc s = small_scene();
  SECTION("up parallel to the view direction") {
    s.camera.up = s.camera.look_at - s.camera.position;
    CHECK_THAT(prepare_error(s), Catch::Contains("parallel"));
    s.camera.up = -(s.camera.look_at - s.camera.position) * 3.0;
    CHECK_THAT(prepare_error(s), Catch::Contains("parallel"));
    s.camera.up = glm::normalize(s.camera.look_at - s.camera.position) + Vec3(1e-13, 0.0, 0.0);
    CHECK_THAT(prepare_error(s), Catch::Contains("parallel"));
  }
  SECTION("zero up") {
    s.camera.up = Vec3(0.0);
    CHECK_THAT(prepare_error(s), Catch::Contains("up"));
  }
  SECTION("zero-size rect light") {
    s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 2.0, 0.5), Vec3(0.5, 0.0, 0.5), 0.0, 1.0, Color(1.0)});
    CHECK_THAT(prepare_error(s), Catch::Contains("rect light") && Catch::Contains("size"));
    std::get<tessera::RectLightDesc>(s.lights.back()).width = 1.0;
    std::get<tessera::RectLightDesc>(s.lights.back()).height = 0.0;
    CHECK_THAT(prepare_error(s), Catch::Contains("rect light") && Catch::Contains("size"));
  }
  SECTION("zero-radius sphere light") {
    s.lights.push_back(tessera::SphereLightDesc{Vec3(0.5, 2.0, 0.5), 0.0, Color(1.0)});
    CHECK_THAT(prepare_error(s), Catch::Contains("sphere light") && Catch::Contains("radius"));
  }
  SECTION("a transfer-function range whose width overflows") {
    // Found next to a fuzz/fuzz_raw_volume finding: float64 data spanning +-1e308 gave
    // range: auto a width of inf, and u = (v - lo) / (hi - lo) was NaN at v = hi (the medium
    // silently vanished there).
    s.tf.lo = -1e308;
    s.tf.hi = 1e308;
    CHECK_THAT(prepare_error(s), Catch::Contains("width"));
  }
  SECTION("fov 0 and 180") {
    s.camera.fov_deg = 0.0;
    CHECK_THAT(prepare_error(s), Catch::Contains("fov"));
    s.camera.fov_deg = 180.0;
    CHECK_THAT(prepare_error(s), Catch::Contains("fov"));
  }
}

TEST_CASE("opacity zero everywhere: the background and lights, no medium work", "[accuracy][stress]") {
  const std::vector<float> field = cloud_field(9, 9, 9);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 9, 9, 9);
  tessera::SceneDesc s = small_scene();
  s.geometry.spacing = Vec3(0.125);
  s.tf.opacity = tessera::ScalarTF::constant(0.0);
  s.image = {12, 12, 16, 0.0};
  SECTION("constant background: exactly the background, alpha 0") {
    for (const bool culling : {true, false}) {
      s.integrator.culling = culling;
      tessera::RenderStats st;
      const tessera::Film film = render(view, s, &st);
      bool exact = true;  // every sample exactly 0.3: the film's sum is 0.3 added n times
      for (const tessera::PixelSums& p : film.pixels()) {
        double sum = 0.0;
        for (std::uint64_t i = 0; i < p.n; ++i) sum += 0.3;
        exact = exact && p.n == 16 && p.r == sum && p.a == 0.0;
      }
      INFO("culling " << culling);
      CHECK(exact);
      CHECK(st.free_flight_lookups == 0);
      CHECK(st.transmittance_lookups == 0);
      CHECK(st.real_collisions == 0);
    }
  }
  SECTION("lights, gradient background, thin lens, multiple scattering; density_scale 0 too") {
    s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 0.5, 1.5), Vec3(0.5, 0.5, 0.0), 0.6, 0.6, Color(3.0)});
    s.lights.push_back(tessera::SphereLightDesc{Vec3(0.2, 0.8, 0.4), 0.2, Color(2.0)});
    s.background.type = tessera::BackgroundType::Gradient;
    s.camera.aperture = 0.1;
    s.integrator.scattering = tessera::Scattering::Multiple;
    tessera::RenderStats st;
    const tessera::Film a = render(view, s, &st);
    CHECK(st.free_flight_lookups == 0);
    CHECK(st.transmittance_lookups == 0);
    CHECK(st.real_collisions == 0);
    CHECK(all_finite(a));
    // Nothing of the field matters: the same image from a zero field and opacity 1, and from
    // opacity 1 with density_scale 0.
    const std::vector<float> zero(field.size(), 0.0f);
    tessera::SceneDesc b = s;
    b.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
    CHECK(bit_identical(a, render(FieldView::contiguous(zero.data(), tessera::DType::Float32, 9, 9, 9), b)));
    tessera::SceneDesc c = s;
    c.tf.opacity = tessera::ScalarTF::constant(1.0);
    c.tf.density_scale = 0.0;
    CHECK(bit_identical(a, render(view, c, &st)));
    CHECK(st.free_flight_lookups == 0);
    double alpha = 0.0;
    for (const tessera::PixelSums& p : a.pixels()) alpha += p.a;
    CHECK(alpha == 0.0);
  }
}
