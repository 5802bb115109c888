// MIS weights sum to one (docs/accuracy.md, "MIS").
//
// The estimator combines next-event estimation (light chosen uniformly, then the light's
// solid-angle pdf) and phase / BRDF sampling with the power heuristic. The two weights of a
// direction sum to one only if both strategies use the same two densities: selection
// probability x light pdf, and the phase / BRDF pdf. If they did not, some radiance would be
// counted more or less than once, and a white furnace would drift from L. So:
//  1. A closed room of 24 inward-facing rect lights of radiance L (each face of an unequal box
//     cut into 2 x 2 rects; selection probability 1/24), black background, a heterogeneous
//     albedo-1 cloud inside, camera inside: every direction from every point meets exactly one
//     front face, so every pixel's expected value is L. Phase shading, and hybrid shading with
//     Lambert-only surfaces (which conserve energy too).
//  2. A constant background L with black rect and sphere lights added: they change nothing but
//     the selection probability (1/5) used in the background's MIS weights.
// Multiple scattering with unbounded depth. Per-pixel chi-square and Bonferroni max |z| at
// alpha = 1e-4 (film sample variance), image mean |z| < 4.
#include <catch2/catch.hpp>

#include "accuracy_support.h"
#include "light_lookup.h"

using namespace tessera_acc;

namespace {

constexpr double kL = 0.8;
constexpr int kN = 17;

tessera::SceneDesc cloud_scene() {
  tessera::SceneDesc s = unit_box_scene(40.0, 1.0);
  s.geometry.spacing = Vec3(1.0 / (kN - 1));
  s.tf.opacity = tessera::ScalarTF({0.0, 0.1, 1.0}, {0.0, 0.3, 1.0});
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 1 << 30;
  s.integrator.phase_g = 0.4;
  s.integrator.macrocell = 4;
  s.image = {12, 12, 256, 0.0};
  s.options.seed = 606;
  return s;
}

/// The six faces of [lo, hi], each cut into 2 x 2 inward-facing rect lights. Rect frames
/// (docs/physics.md section 7): x faces: width along y, height along z; y faces: width along
/// x, height along z; z faces: width along x, height along y.
void add_room(tessera::SceneDesc& s, const Vec3& lo, const Vec3& hi) {
  const Vec3 size = hi - lo, c = 0.5 * (lo + hi);
  for (int axis = 0; axis < 3; ++axis) {
    const int wa = axis == 0 ? 1 : 0, ha = axis == 2 ? 1 : 2;  // width and height axes
    for (const double side : {-1.0, 1.0}) {
      for (const double sw : {-0.25, 0.25})
        for (const double sh : {-0.25, 0.25}) {
          Vec3 p = c;
          p[axis] = side < 0 ? lo[axis] : hi[axis];
          p[wa] += sw * size[wa];
          p[ha] += sh * size[ha];
          Vec3 target = p;
          target[axis] -= side;  // face inward
          s.lights.push_back(tessera::RectLightDesc{p, target, 0.5 * size[wa], 0.5 * size[ha], Color(kL)});
        }
    }
  }
}

void check_furnace(const tessera::SceneDesc& s, const std::vector<float>& field, const char* what) {
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::RenderStats st;
  const tessera::Film film = render(view, s, &st);
  const PixelTest t = compare_to_expected(film, std::vector<double>(film.pixels().size(), kL));
  const ImageMean m = image_mean(film);
  INFO(what << ": " << t.describe() << "; image mean " << m.mean << " +- " << m.se << ", real collisions per sample "
            << static_cast<double>(st.real_collisions) / st.samples);
  CHECK(st.real_collisions > st.samples);  // multiple scattering happens
  CHECK(t.ok());
  CHECK(m.z(kL) < 4.0);
}

}  // namespace

TEST_CASE("MIS: a room of 24 rect lights keeps a white furnace at L", "[accuracy][mis]") {
  const std::vector<float> field = cloud_field(kN, kN, kN);
  tessera::SceneDesc s = cloud_scene();
  add_room(s, Vec3(-1.0, -0.8, -1.3), Vec3(2.2, 1.9, 2.5));
  REQUIRE(tessera::count_lights<tessera::RectLightDesc>(s.lights) == 24);
  s.camera.position = Vec3(0.6, 0.4, -0.9);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 50.0;
  SECTION("phase shading") { check_furnace(s, field, "phase"); }
  SECTION("hybrid shading, Lambert surfaces") {
    s.integrator.shading = tessera::Shading::Hybrid;
    s.integrator.gradient_factor = 3.0;
    check_furnace(s, field, "hybrid");
  }
}

TEST_CASE("MIS: black lights change only the selection probability of the background", "[accuracy][mis]") {
  const std::vector<float> field = cloud_field(kN, kN, kN);
  tessera::SceneDesc s = cloud_scene();
  s.background.color = Color(kL);
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 1.6, 0.5), Vec3(0.5, 0.0, 0.5), 0.8, 0.8, Color(0.0)});
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 0.5, 0.5), Vec3(1.5, 0.5, 0.5), 0.4, 0.4, Color(0.0)});  // inside
  s.lights.push_back(tessera::RectLightDesc{Vec3(-0.6, 0.2, 0.4), Vec3(0.5, 0.5, 0.5), 0.5, 0.3, Color(0.0)});
  s.lights.push_back(tessera::SphereLightDesc{Vec3(1.4, 0.3, 0.6), 0.25, Color(0.0)});
  s.camera.position = Vec3(1.8, 1.3, -1.6);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 32.0;
  check_furnace(s, field, "background + 4 black lights");
}
