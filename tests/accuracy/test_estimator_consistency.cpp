// Estimator consistency (docs/accuracy.md, "Consistency"): choices that must not change the
// expected image, on a scene that exercises every path of the estimator (heterogeneous
// cloud, hybrid shading with specular, emission, rect + sphere light + gradient background,
// multiple scattering).
//  - Statistically equal (independent seeds): delta vs ratio tracking of shadow rays (with and
//    without roulette; also behind a thick absorber with a loose majorant, where most shadow
//    rays go through the roulette), global vs grid majorant (macrocells 1, 2, 4). Per-pixel chi-square and
//    Bonferroni max |z| of the difference at alpha = 1e-4, and the signed difference of the
//    image means within 3 standard errors.
//  - Bit-identical where the random streams are the same: tiled vs scanline vs Morton order
//    and thread counts; a grid whose single macrocell covers the volume vs the global
//    majorant; delta vs ratio tracking when no shadow ray is ever traced (no light).
#include <catch2/catch.hpp>

#include "accuracy_support.h"

using namespace tessera_acc;

namespace {

constexpr int kN = 17;

tessera::SceneDesc busy_scene() {
  tessera::SceneDesc s = unit_box_scene(25.0, 0.0);
  s.geometry.spacing = Vec3(1.0 / (kN - 1));
  s.tf.opacity = tessera::ScalarTF({0.0, 0.1, 0.6, 1.0}, {0.0, 0.2, 1.0, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.9, 0.7, 0.5), Color(0.6, 0.8, 0.95)});
  s.tf.specular = tessera::ColorTF::constant(Color(0.05));
  s.tf.roughness = tessera::ScalarTF({0.0, 1.0}, {0.3, 0.7});
  s.tf.emission = tessera::ColorTF({0.0, 0.7, 1.0}, {Color(0.0), Color(0.0), Color(1.5, 0.6, 0.2)});
  s.camera.position = Vec3(1.6, 1.1, -1.8);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 34.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 1.8, 0.4), Vec3(0.5, 0.0, 0.5), 1.0, 0.7, Color(4.0, 3.5, 3.0)});
  s.lights.push_back(tessera::SphereLightDesc{Vec3(-0.9, 0.4, 0.2), 0.3, Color(3.0, 3.0, 5.0)});
  s.background.type = tessera::BackgroundType::Gradient;
  s.background.top = Color(0.5, 0.6, 0.9);
  s.background.middle = Color(0.3);
  s.background.bottom = Color(0.05);
  s.background.up = Vec3(0.0, 1.0, 0.0);
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 8;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.gradient_factor = 2.0;
  s.integrator.phase_g = 0.3;
  s.integrator.macrocell = 4;
  s.image = {16, 16, 512, 0.0};
  s.options.seed = 700;
  return s;
}

void check_equal_expectation(const tessera::Film& a, const tessera::Film& b, const std::string& what) {
  const PixelTest t = compare_films(a, b);
  INFO(what << ": " << t.describe());
  CHECK(t.ok());
  CHECK(std::fabs(t.mean_diff) < 3.0 * t.mean_diff_se);
}

}  // namespace

TEST_CASE("delta and ratio tracking of shadow rays: equal expected images", "[accuracy][consistency]") {
  const std::vector<float> field = cloud_field(kN, kN, kN);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::SceneDesc s = busy_scene();
  s.integrator.shadow = tessera::ShadowMode::Ratio;
  const tessera::Film ratio = render(view, s);
  s.options.seed = 701;
  s.integrator.shadow_roulette = false;
  const tessera::Film ratio_nr = render(view, s);
  s.options.seed = 702;
  s.integrator.shadow = tessera::ShadowMode::Delta;
  const tessera::Film delta = render(view, s);
  REQUIRE(image_mean(ratio).mean > 20.0 * image_mean(ratio).se);  // the test has signal
  check_equal_expectation(ratio, delta, "ratio vs delta");
  check_equal_expectation(ratio_nr, delta, "ratio without roulette vs delta");
  check_equal_expectation(ratio, ratio_nr, "ratio with vs without roulette");
}

TEST_CASE("delta and ratio tracking behind a thick absorber with a loose majorant", "[accuracy][consistency]") {
  // Shadow rays from a thin scattering layer (y > 0.5) cross an absorbing layer (y < 0.5,
  // optical depth 2) to a rect light below; one hot vertex sets the global majorant to twice
  // the absorber's extinction, so ratio tracking halves its estimate per event and most shadow
  // rays go through the roulette below 0.1. Its survivors' weight is what this checks.
  std::vector<float> field(kN * kN * kN);
  for (int k = 0; k < kN; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i) field[(k * kN + j) * kN + i] = j < kN / 2 ? 0.5f : 0.1f;
  field.back() = 1.0f;
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::SceneDesc s = unit_box_scene(8.0, 1.0);
  s.geometry.spacing = Vec3(1.0 / (kN - 1));
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  s.integrator.majorant = tessera::MajorantMode::Global;
  s.camera.position = Vec3(0.5, 0.75, -2.5);
  s.camera.look_at = Vec3(0.5, 0.75, 0.5);
  s.camera.fov_deg = 9.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, -0.01, 0.5), Vec3(0.5, 1.0, 0.5), 0.6, 0.6, Color(100.0)});
  s.image = {16, 16, 4096, 0.0};
  s.options.seed = 720;
  s.integrator.shadow = tessera::ShadowMode::Ratio;
  const tessera::Film ratio = render(view, s);
  s.options.seed = 721;
  s.integrator.shadow_roulette = false;
  const tessera::Film ratio_nr = render(view, s);
  s.options.seed = 722;
  s.integrator.shadow = tessera::ShadowMode::Delta;
  const tessera::Film delta = render(view, s);
  REQUIRE(image_mean(ratio_nr).mean > 20.0 * image_mean(ratio_nr).se);
  check_equal_expectation(ratio, delta, "behind an absorber: ratio vs delta");
  check_equal_expectation(ratio_nr, delta, "behind an absorber: ratio without roulette vs delta");
  check_equal_expectation(ratio, ratio_nr, "behind an absorber: ratio with vs without roulette");
}

TEST_CASE("global and grid majorants: equal expected images", "[accuracy][consistency]") {
  const std::vector<float> field = cloud_field(kN, kN, kN);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::SceneDesc s = busy_scene();
  s.integrator.majorant = tessera::MajorantMode::Global;
  s.options.seed = 710;
  tessera::RenderStats st_global;
  const tessera::Film global = render(view, s, &st_global);
  for (const int edge : {1, 2, 4}) {
    tessera::SceneDesc g = s;
    g.integrator.majorant = tessera::MajorantMode::Grid;
    g.integrator.macrocell = edge;
    g.options.seed = 711 + edge;
    tessera::RenderStats st;
    const tessera::Film grid = render(view, g, &st);
    check_equal_expectation(grid, global, "macrocell " + std::to_string(edge) + " vs global");
    // Tighter majorants reject fewer tentative collisions per real one.
    CHECK(static_cast<double>(st.null_collisions) / st.real_collisions <
          static_cast<double>(st_global.null_collisions) / st_global.real_collisions);
  }
}

TEST_CASE("bit-identical images where the random streams are the same", "[accuracy][consistency]") {
  const std::vector<float> field = cloud_field(kN, kN, kN);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::SceneDesc s = busy_scene();
  s.image = {21, 19, 8, 0.0};  // partial tiles at the right and bottom
  const tessera::Film base = render(view, s);
  SECTION("tiled vs scanline vs Morton, 1 vs 2 threads") {
    for (const int tile : {0, 1, 5, 64}) {
      for (const auto order : {tessera::TileOrder::RowMajor, tessera::TileOrder::Morton}) {
        for (const int threads : {1, 2}) {
          tessera::SceneDesc d = s;
          d.options.tile = tile;
          d.options.order = order;
          d.options.threads = threads;
          INFO("tile " << tile << ", order " << static_cast<int>(order) << ", threads " << threads);
          CHECK(bit_identical(render(view, d), base));
        }
      }
    }
  }
  SECTION("one macrocell over the whole volume is the global majorant") {
    tessera::SceneDesc a = s, b = s;
    a.integrator.majorant = tessera::MajorantMode::Grid;
    a.integrator.macrocell = kN - 1;
    b.integrator.majorant = tessera::MajorantMode::Global;
    CHECK(bit_identical(render(view, a), render(view, b)));
  }
  SECTION("delta vs ratio shadow rays when no light is ever sampled") {
    tessera::SceneDesc a = s;
    a.lights.clear();
    a.background.type = tessera::BackgroundType::Constant;
    a.background.color = Color(0.0);  // black: not a light; only emission remains
    tessera::SceneDesc b = a;
    a.integrator.shadow = tessera::ShadowMode::Ratio;
    b.integrator.shadow = tessera::ShadowMode::Delta;
    tessera::RenderStats st;
    const tessera::Film fa = render(view, a, &st);
    CHECK(st.transmittance_lookups == 0);
    CHECK(image_mean(fa).mean > 0.0);
    CHECK(bit_identical(fa, render(view, b)));
  }
}
