// Transmittance through absorbing media against Beer-Lambert, rendered end to end: a purely
// absorbing box (albedo 0) in front of a constant background of radiance 1, seen by a narrow
// pinhole camera looking along +z, so that each pixel's expected radiance is exp(-tau) and its
// expected alpha 1 - exp(-tau). Then ratio vs delta tracking of shadow rays agree.
//
// Statistics: every comparison is a two-sided z-test with |z| < 4 (per-test false-alarm
// probability 6.3e-5); the standard error comes from the film's per-pixel sample variance.
// Seeds are fixed, so the outcome is reproducible.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

namespace {

constexpr int kN = 5;  // vertices per axis of the box fields (4 voxels)

/// Places the camera on the box's axis 10 depths in front of it (looking along +z) with a fov
/// whose footprint on the back face stays within 40% of the box's half-width: every camera ray
/// crosses the box through its front and back faces.
void frame_box(tessera::SceneDesc& s, const Vec3& lo, const Vec3& hi) {
  const Vec3 c = 0.5 * (lo + hi);
  const double depth = hi.z - lo.z, half = 0.5 * std::min(hi.x - lo.x, hi.y - lo.y);
  s.camera.position = Vec3(c.x, c.y, lo.z - 10.0 * depth);
  s.camera.look_at = Vec3(c.x, c.y, lo.z);
  s.camera.fov_deg = 2.0 * std::atan(0.4 * half / (11.0 * depth)) * 180.0 / tessera::kPi;
}

/// A box field seen straight on along +z (frame_box); albedo 0, constant background 1, no
/// other light.
tessera::SceneDesc absorbing_box(const tessera::VolumeGeometry& g, double density_scale) {
  tessera::SceneDesc s;
  s.geometry = g;
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = density_scale;
  s.tf.opacity = tessera::ScalarTF::constant(1.0);
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.0));
  const Vec3 lo = g.origin, hi = g.origin + Vec3(kN - 1) * g.spacing;
  frame_box(s, lo, hi);
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(1.0);
  s.integrator.shading = tessera::Shading::Phase;
  s.image = {16, 16, 128, 0.0};
  s.options.seed = 2024;
  return s;
}

/// Expected mean transmittance over the image for a medium whose optical depth along +z
/// through the box is tau_z: each ray's path is tau_z / d.z, averaged over a 4x4 grid of
/// points per pixel (the camera's own ray generator, so the geometry is exactly the renderer's).
double expected_transmittance(const tessera::SceneDesc& s, double tau_z) {
  const tessera::Camera cam(s.camera, s.image.width, s.image.height);
  double sum = 0.0;
  int n = 0;
  for (int y = 0; y < s.image.height; ++y)
    for (int x = 0; x < s.image.width; ++x)
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) {
          const tessera::Ray r = cam.generate(x + (sx + 0.5) / 4, y + (sy + 0.5) / 4, 0.5, 0.5);
          sum += std::exp(-tau_z / r.d.z);
          ++n;
        }
  return sum / n;
}

struct BoxResult {
  tessera_test::MeanWithError L;
  double red, alpha;
  bool complementary;  ///< every pixel: sum of L + sum of alpha == sample count, exactly
  tessera::RenderStats stats;
};

BoxResult render_box(const std::vector<float>& field, const tessera::SceneDesc& s) {
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  BoxResult r;
  const tessera::Film film = tessera_test::render_film(ps, &r.stats);
  r.L = tessera_test::luminance_stats(film);
  r.red = tessera_test::mean_red(film);
  r.alpha = tessera_test::mean_alpha(film);
  r.complementary = true;
  for (const tessera::PixelSums& p : film.pixels())
    r.complementary = r.complementary && p.r + p.a == static_cast<double>(p.n);
  return r;
}

void check_box(const BoxResult& r, double T) {
  INFO("expected T " << T << ", mean L " << r.L.mean << " +- " << r.L.se << ", red " << r.red << ", alpha " << r.alpha);
  CHECK(r.L.se > 0.0);
  CHECK(r.L.z(T) < 4.0);
  CHECK(std::fabs(r.red - T) < 4.0 * r.L.se);
  // Alpha is 1 on a collision and 0 on escape, L the opposite: same standard error.
  CHECK(std::fabs(r.alpha - (1.0 - T)) < 4.0 * r.L.se);
  CHECK(r.complementary);
  CHECK(r.stats.discarded_samples == 0);
}

}  // namespace

TEST_CASE("homogeneous absorbing box: pixel radiance exp(-sigma_t d), alpha 1 - exp(-sigma_t d)",
          "[transmittance][render]") {
  const std::vector<float> field = tessera_test::constant_field(kN, kN, kN, 1.0f);
  struct Case {
    const char* name;
    tessera::VolumeGeometry g;
  };
  const Case cases[] = {
      {"unit spacing at the origin", {Vec3(0.0), Vec3(1.0)}},
      {"anisotropic spacing, offset origin", {Vec3(-3.0, 1.0, 10.0), Vec3(0.5, 0.25, 2.0)}},
  };
  for (const Case& c : cases) {
    const double depth = (kN - 1) * c.g.spacing.z;
    for (const double tau : {0.5, 2.0, 4.0}) {
      tessera::SceneDesc s = absorbing_box(c.g, tau / depth);
      const double T = expected_transmittance(s, tau);
      SECTION(std::string(c.name) + ", tau " + std::to_string(tau)) {
        SECTION("delta tracking, grid majorant, macrocell 2") {
          s.integrator.majorant = tessera::MajorantMode::Grid;
          s.integrator.macrocell = 2;
          check_box(render_box(field, s), T);
        }
        SECTION("delta tracking, grid majorant, macrocell 1") {
          s.integrator.majorant = tessera::MajorantMode::Grid;
          s.integrator.macrocell = 1;
          check_box(render_box(field, s), T);
        }
        SECTION("delta tracking, global majorant") {
          s.integrator.majorant = tessera::MajorantMode::Global;
          check_box(render_box(field, s), T);
        }
        SECTION("multiple scattering changes nothing at albedo 0") {
          s.integrator.scattering = tessera::Scattering::Multiple;
          s.integrator.max_bounces = 1000;
          check_box(render_box(field, s), T);
        }
      }
    }
  }
}

TEST_CASE("emissive absorber: radiance Le (1 - exp(-tau)) over a black background", "[transmittance][render]") {
  // Emission is collected at real collisions (emission coefficient sigma_t Le): a sample is
  // Le when the camera ray collides and 0 when it escapes into the black background.
  const std::vector<float> field = tessera_test::constant_field(kN, kN, kN, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  const tessera::VolumeGeometry g{Vec3(0.0), Vec3(1.0)};
  for (const double tau : {0.3, 1.5}) {
    for (const auto sc : {tessera::Scattering::Single, tessera::Scattering::Multiple}) {
      tessera::SceneDesc s = absorbing_box(g, tau / 4.0);
      s.background.color = Color(0.0);
      s.tf.emission = tessera::ColorTF::constant(Color(2.0));
      s.integrator.scattering = sc;
      const double T = expected_transmittance(s, tau);
      const tessera::PreparedScene ps = tessera::prepare(view, s);
      const tessera::Film film = tessera_test::render_film(ps);
      const auto L = tessera_test::luminance_stats(film);
      INFO("tau " << tau << ": expected " << 2.0 * (1.0 - T) << ", got " << L.mean << " +- " << L.se);
      CHECK(L.z(2.0 * (1.0 - T)) < 4.0);
      CHECK(std::fabs(tessera_test::mean_alpha(film) - (1.0 - T)) < 4.0 * L.se / 2.0);
    }
  }
}

TEST_CASE("heterogeneous absorbers along the view axis: exp(-integral of sigma_t)", "[transmittance][render]") {
  // v = k (the z index) over 5 x 5 x 9 vertices, range [0, 8]: u = z / D along the depth D.
  constexpr int nz = 9;
  std::vector<float> field(kN * kN * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i) field[(k * kN + j) * kN + i] = static_cast<float>(k);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, nz);
  tessera::VolumeGeometry g{Vec3(0.0), Vec3(1.0, 1.0, 0.5)};
  const double D = (nz - 1) * g.spacing.z;

  auto scene = [&](double s_scale, const tessera::ScalarTF& opacity) {
    tessera::SceneDesc s = absorbing_box(g, s_scale);
    s.tf.lo = 0.0;
    s.tf.hi = nz - 1.0;
    s.tf.opacity = opacity;
    frame_box(s, g.origin, g.origin + Vec3(kN - 1, kN - 1, nz - 1) * g.spacing);  // deeper box
    return s;
  };
  struct Case {
    const char* name;
    tessera::ScalarTF opacity;
    double depth_fraction;  ///< integral of opacity(u) du over [0, 1]
    bool null_events;       ///< some macrocell holds varying extinction
  };
  const Case cases[] = {
      {"linear opacity: sigma = s z / D", tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0}), 0.5, true},
      {"kinked opacity: sigma = s min(1, 2 z / D)", tessera::ScalarTF({0.0, 0.5, 1.0}, {0.0, 1.0, 1.0}), 0.75, true},
      // The step sits on a macrocell face (z index 2): every cell is homogeneous, and the
      // cells before the step have majorant 0 and are crossed without any lookup.
      {"step opacity: 0 then 1 at z = D / 4", tessera::ScalarTF({0.25, 0.25}, {0.0, 1.0}), 0.75, false},
  };
  for (const Case& c : cases) {
    for (const auto mode : {tessera::MajorantMode::Grid, tessera::MajorantMode::Global}) {
      tessera::SceneDesc s = scene(3.0 / D, c.opacity);
      s.integrator.majorant = mode;
      s.integrator.macrocell = 2;
      const double T = expected_transmittance(s, 3.0 * c.depth_fraction);
      const tessera::PreparedScene ps = tessera::prepare(view, s);
      tessera::RenderStats st;
      const tessera::Film film = tessera_test::render_film(ps, &st);
      const auto L = tessera_test::luminance_stats(film);
      INFO(c.name << (mode == tessera::MajorantMode::Grid ? ", grid" : ", global") << ": expected " << T << ", got "
                  << L.mean << " +- " << L.se);
      CHECK(L.z(T) < 4.0);
      CHECK(std::fabs(tessera_test::mean_alpha(film) - (1.0 - T)) < 4.0 * L.se);
      if (c.null_events && mode == tessera::MajorantMode::Grid) CHECK(st.null_collisions > 0);
      if (!c.null_events && mode == tessera::MajorantMode::Grid) CHECK(st.null_collisions == 0);
    }
  }
}

TEST_CASE("ratio and delta tracking of shadow rays estimate the same transmittance", "[transmittance][render]") {
  // A heterogeneous scattering cloud lit by a rect light, a sphere light and the background;
  // only the shadow-ray estimator differs between the renders, each with its own seed, so
  // the image means are independent estimates of the same expectation.
  constexpr int N = 16;
  const std::vector<float> field = tessera_test::blobby_field(N, N, N);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, N, N, N);
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (N - 1));
  s.tf.density_scale = 12.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.1, 1.0}, {0.0, 0.4, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.9));
  s.camera.position = Vec3(0.5, 0.5, -2.5);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 25.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 2.0, 0.5), Vec3(0.5, 0.0, 0.5), 1.0, 1.0, Color(4.0)});
  s.lights.push_back(tessera::SphereLightDesc{Vec3(-1.5, 0.5, 0.2), 0.3, Color(6.0)});
  s.background.color = Color(0.3);
  s.background.visible = false;  // camera sees only scattered light: more signal in the mean
  s.integrator.shading = tessera::Shading::Phase;
  s.integrator.phase_g = 0.3;
  s.image = {16, 16, 256, 0.0};

  auto run = [&](tessera::Scattering sc, tessera::ShadowMode mode, bool roulette, std::uint64_t seed) {
    tessera::SceneDesc d = s;
    d.integrator.scattering = sc;
    d.integrator.max_bounces = 8;
    d.integrator.shadow = mode;
    d.integrator.shadow_roulette = roulette;
    d.options.seed = seed;
    const tessera::PreparedScene ps = tessera::prepare(view, d);
    return tessera_test::luminance_stats(tessera_test::render_film(ps));
  };
  for (const auto sc : {tessera::Scattering::Single, tessera::Scattering::Multiple}) {
    const auto ratio = run(sc, tessera::ShadowMode::Ratio, true, 1);
    const auto ratio_nr = run(sc, tessera::ShadowMode::Ratio, false, 2);
    const auto delta = run(sc, tessera::ShadowMode::Delta, true, 3);
    INFO((sc == tessera::Scattering::Single ? "single" : "multiple")
         << ": ratio " << ratio.mean << " +- " << ratio.se << ", ratio without roulette " << ratio_nr.mean << " +- "
         << ratio_nr.se << ", delta " << delta.mean << " +- " << delta.se);
    REQUIRE(ratio.mean > 0.01);  // the test has signal
    CHECK(std::fabs(ratio.mean - delta.mean) / std::hypot(ratio.se, delta.se) < 4.0);
    CHECK(std::fabs(ratio_nr.mean - delta.mean) / std::hypot(ratio_nr.se, delta.se) < 4.0);
    CHECK(std::fabs(ratio.mean - ratio_nr.mean) / std::hypot(ratio.se, ratio_nr.se) < 4.0);
  }
}

TEST_CASE("ratio tracking with roulette stays unbiased behind a thick absorber", "[transmittance][render]") {
  // A thin scattering layer (y > 0.5) lit only through a thicker absorbing layer (y < 0.5) by
  // a rect light below the box. The global majorant is set by one hot vertex at twice the
  // absorber's extinction, so ratio tracking multiplies by 1/2 per absorber event and most
  // shadow rays fall under the roulette threshold (T < 0.1). Ratio tracking with and without
  // roulette and delta tracking must agree (independent seeds; |z| < 4 pairwise).
  constexpr int N = 17;
  std::vector<float> field(N * N * N);
  for (int k = 0; k < N; ++k)
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) field[(k * N + j) * N + i] = j < N / 2 ? 0.5f : 0.1f;
  field[N * N * N - 1] = 1.0f;  // far top corner: sets the global majorant to density_scale
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, N, N, N);
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (N - 1));
  s.tf.density_scale = 10.0;  // absorber sigma 5 (tau 2.5 across it), scatterer sigma 1
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(Color(1.0));
  s.camera.position = Vec3(0.5, 0.75, -2.5);
  s.camera.look_at = Vec3(0.5, 0.75, 0.5);
  s.camera.fov_deg = 9.0;
  // Small and just under the box: every shadow ray crosses the whole absorber.
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, -0.01, 0.5), Vec3(0.5, 1.0, 0.5), 0.6, 0.6, Color(200.0)});
  s.background.color = Color(0.0);
  s.integrator.scattering = tessera::Scattering::Single;
  s.integrator.shading = tessera::Shading::Phase;
  s.integrator.majorant = tessera::MajorantMode::Global;
  s.image = {16, 16, 256, 0.0};

  auto run = [&](tessera::ShadowMode mode, bool roulette, std::uint64_t seed) {
    tessera::SceneDesc d = s;
    d.integrator.shadow = mode;
    d.integrator.shadow_roulette = roulette;
    d.options.seed = seed;
    return tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(view, d)));
  };
  const auto ratio = run(tessera::ShadowMode::Ratio, true, 11);
  const auto ratio_nr = run(tessera::ShadowMode::Ratio, false, 12);
  const auto delta = run(tessera::ShadowMode::Delta, true, 13);
  INFO("ratio " << ratio.mean << " +- " << ratio.se << ", ratio without roulette " << ratio_nr.mean << " +- "
                << ratio_nr.se << ", delta " << delta.mean << " +- " << delta.se);
  REQUIRE(ratio_nr.mean > 20.0 * ratio_nr.se);  // the test has signal
  CHECK(std::fabs(ratio.mean - delta.mean) / std::hypot(ratio.se, delta.se) < 4.0);
  CHECK(std::fabs(ratio_nr.mean - delta.mean) / std::hypot(ratio_nr.se, delta.se) < 4.0);
  CHECK(std::fabs(ratio.mean - ratio_nr.mean) / std::hypot(ratio.se, ratio_nr.se) < 4.0);
}
