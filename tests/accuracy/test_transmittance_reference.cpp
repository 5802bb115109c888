// Reference (a): per-pixel transmittance through a homogeneous absorbing box, pinhole and
// thin lens (docs/accuracy.md, "Transmittance per pixel").
//
// Albedo 0, constant background 1, no other light: a camera sample is 1 when its ray escapes
// the box without a real collision and 0 otherwise, so a pixel's sample count of escapes is
// Binomial(n, T_pix) with
//   T_pix = E_{pixel point, lens point}[ exp(-sigma_t * chord(ray)) ],
// chord = length of the ray inside the box. T_pix is integrated here with the independent
// reference camera (accuracy_support.h): a 64 x 64 midpoint grid per pixel for a pinhole,
// 2^15 points of the R_4 sequence over pixel x lens for a thin lens.
//
// Test: per-pixel z = (mean - T_pix) / sqrt(T_pix (1 - T_pix) / n) (exact binomial variance),
// chi-square over pixels and Bonferroni max |z|, alpha = 1e-4, and the image mean of the
// tested pixels within 4 standard errors (two-sided 6.3e-5); pixels where escapes or
// collisions are too rare for the normal approximation (expected count < 10) are pooled into
// exact Poisson tests (compare_binomial). Alpha (A) must equal 1 - radiance sample by sample,
// i.e. the sums of A and L add up to n exactly.
#include <catch2/catch.hpp>

#include "accuracy_support.h"

using namespace tessera_acc;

namespace {

constexpr int kN = 3;  // vertices per axis: 2 voxels, so the macrocell walk has cells to cross

struct Case {
  const char* name;
  tessera::CameraDesc cam;
  tessera::MajorantMode majorant;
  int macrocell;
};

void check_case(const Case& c, double sigma) {
  const std::vector<float> field = constant_field(kN, kN, kN, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::SceneDesc s = unit_box_scene(sigma, 0.0);
  s.geometry.spacing = Vec3(1.0 / (kN - 1));
  s.background.color = Color(1.0);
  s.camera = c.cam;
  s.integrator.majorant = c.majorant;
  s.integrator.macrocell = c.macrocell;
  s.image = {16, 16, 4096, 0.0};
  s.options.seed = 101;

  const Vec3 lo(0.0), hi(1.0);
  const std::vector<double> T = expected_image(
      s, 64, [&](const Ray& r) { return std::exp(-sigma * chord(r, lo, hi)); }, 1 << 15);
  tessera::RenderStats st;
  const tessera::Film film = render(view, s, &st);
  const PixelTest t = compare_binomial(film, T, 1.0);
  bool complementary = true;
  for (const tessera::PixelSums& p : film.pixels())
    complementary = complementary && p.r + p.a == static_cast<double>(p.n);
  double tmin = 1.0;
  for (double v : T) tmin = std::min(tmin, v);
  INFO(c.name << ", sigma " << sigma << ": " << t.describe() << ", min T_pix " << tmin);
  CHECK(tmin < 0.7);  // the test has signal: the box is seen through its thick part
  CHECK(t.ok());
  CHECK(t.mean_z() < 4.0);  // a small bias shared by all pixels shows in the image mean first
  CHECK(complementary);
  CHECK(st.discarded_samples == 0);
}

}  // namespace

TEST_CASE("transmittance per pixel through an absorbing box: pinhole and thin lens", "[accuracy][transmittance]") {
  tessera::CameraDesc oblique;
  oblique.position = Vec3(2.1, 1.6, -1.7);
  oblique.look_at = Vec3(0.5, 0.45, 0.55);
  oblique.up = Vec3(0.0, 1.0, 0.0);
  oblique.fov_deg = 40.0;

  tessera::CameraDesc lens = oblique;
  lens.aperture = 0.25;  // focused on look_at

  tessera::CameraDesc lens_near = oblique;
  lens_near.aperture = 0.6;
  lens_near.focus_distance = 1.2;  // focal plane in front of the box: strong blur
  lens_near.up = Vec3(0.3, 0.0, 1.0);

  const Case cases[] = {
      {"pinhole, grid majorant (macrocell 1)", oblique, tessera::MajorantMode::Grid, 1},
      {"pinhole, global majorant", oblique, tessera::MajorantMode::Global, 16},
      {"thin lens focused on the box", lens, tessera::MajorantMode::Grid, 1},
      {"thin lens, near focus, tilted up", lens_near, tessera::MajorantMode::Grid, 1},
  };
  for (const Case& c : cases) {
    SECTION(c.name) { check_case(c, 1.5); }
  }
}

TEST_CASE("transmittance per pixel: thick and thin boxes", "[accuracy][transmittance]") {
  tessera::CameraDesc cam;
  cam.position = Vec3(-1.2, 2.0, 2.4);
  cam.look_at = Vec3(0.5, 0.5, 0.5);
  cam.up = Vec3(0.0, 0.0, 1.0);
  cam.fov_deg = 45.0;
  for (const double sigma : {0.05, 6.0}) {
    SECTION("sigma " + std::to_string(sigma)) {
      const Case c{"pinhole from above", cam, tessera::MajorantMode::Grid, 1};
      const std::vector<float> field = constant_field(kN, kN, kN, 1.0f);
      const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
      tessera::SceneDesc s = unit_box_scene(sigma, 0.0);
      s.geometry.spacing = Vec3(1.0 / (kN - 1));
      s.background.color = Color(1.0);
      s.camera = c.cam;
      s.image = {16, 16, 512, 0.0};
      s.options.seed = 102;
      const std::vector<double> T =
          expected_image(s, 64, [&](const Ray& r) { return std::exp(-sigma * chord(r, Vec3(0.0), Vec3(1.0))); });
      const PixelTest t = compare_binomial(render(view, s), T, 1.0);
      INFO(t.describe());
      CHECK(t.ok());
      CHECK(t.mean_z() < 4.0);
    }
  }
}
