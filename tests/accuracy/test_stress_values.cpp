// Stress: extreme field values and densities (docs/accuracy.md, "Stress"). Every render must
// give finite pixels and discard nothing, and the right answer where one is known:
//  - NaN and -Inf vertices read as lo and +Inf as hi (docs/physics.md section 1): a field
//    with them renders bit-identically to the field with those substitutions made;
//  - 1e30 (-1e30) everywhere is clamped to u = 1 (u = 0): bit-identical to hi (lo) everywhere;
//  - denormal vertex values: with a range [0, 1] they are "no medium" (bit-identical to a zero
//    field); with a denormal range [0, 2^-126 * 2^-4] they are an ordinary field, equal within
//    noise to the same field at unit scale;
//  - density_scale 1e-8 ... 1e8 through an absorbing box: per-pixel binomial test against
//    E[exp(-sigma chord)] (reference (a)), alpha = 1e-4.
#include <catch2/catch.hpp>

#include "accuracy_support.h"

#include <limits>

using namespace tessera_acc;

namespace {

constexpr int kN = 13;

tessera::SceneDesc lit_cloud() {
  tessera::SceneDesc s = unit_box_scene(20.0, 0.85);
  s.geometry.spacing = Vec3(1.0 / (kN - 1));
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.1, 1.0}, {0.0, 0.3, 1.0});
  s.tf.emission = tessera::ColorTF({0.0, 0.8, 1.0}, {Color(0.0), Color(0.0), Color(2.0)});
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 12;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.camera.position = Vec3(1.5, 1.1, -1.6);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 35.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 1.8, 0.5), Vec3(0.5, 0.0, 0.5), 0.8, 0.8, Color(4.0)});
  s.background.color = Color(0.2);
  s.image = {16, 16, 16, 0.0};
  s.options.seed = 900;
  return s;
}

template <class T>
FieldView view_of(const std::vector<T>& f, tessera::DType dt) {
  return FieldView::contiguous(f.data(), dt, kN, kN, kN);
}

}  // namespace

TEMPLATE_TEST_CASE("NaN and +-Inf vertices render as lo / hi substitutes, bit for bit", "[accuracy][stress]", float,
                   double) {
  const tessera::DType dt = std::is_same_v<TestType, float> ? tessera::DType::Float32 : tessera::DType::Float64;
  const std::vector<float> base = cloud_field(kN, kN, kN);
  std::vector<TestType> bad(base.begin(), base.end()), subst(base.begin(), base.end());
  const TestType nan = std::numeric_limits<TestType>::quiet_NaN(), inf = std::numeric_limits<TestType>::infinity();
  std::uint64_t nans = 0;
  for (std::size_t i = 0; i < bad.size(); i += 7) {
    switch ((i / 7) % 3) {
      case 0: bad[i] = nan, subst[i] = 0, ++nans; break;  // lo = 0
      case 1: bad[i] = inf, subst[i] = 1; break;          // hi = 1
      default: bad[i] = -inf, subst[i] = 0; break;
    }
  }
  const tessera::SceneDesc s = lit_cloud();
  tessera::RenderStats st;
  const tessera::Film a = render(view_of(bad, dt), s, &st);
  const tessera::Film b = render(view_of(subst, dt), s);
  CHECK(all_finite(a));
  CHECK(st.discarded_samples == 0);
  CHECK(st.nan_voxels_seen == nans);
  CHECK(bit_identical(a, b));
}

TEST_CASE("+-1e30 everywhere renders as hi / lo everywhere, bit for bit", "[accuracy][stress]") {
  const tessera::SceneDesc s = lit_cloud();
  for (const float big : {1e30f, -1e30f}) {
    const std::vector<float> f(kN * kN * kN, big), ref(kN * kN * kN, big > 0 ? 1.0f : 0.0f);
    tessera::RenderStats st;
    const tessera::Film a = render(view_of(f, tessera::DType::Float32), s, &st);
    INFO("value " << big);
    CHECK(all_finite(a));
    CHECK(bit_identical(a, render(view_of(ref, tessera::DType::Float32), s)));
  }
  // Mixed: 1e30 spikes in the cloud interpolate to huge values that clamp; finite pixels.
  std::vector<float> spiky = cloud_field(kN, kN, kN);
  for (std::size_t i = 3; i < spiky.size(); i += 11) spiky[i] = (i % 2) ? 1e30f : -1e30f;
  tessera::RenderStats st;
  const tessera::Film f = render(view_of(spiky, tessera::DType::Float32), s, &st);
  CHECK(all_finite(f));
  CHECK(st.discarded_samples == 0);
}

TEST_CASE("denormal field values", "[accuracy][stress]") {
  const std::vector<float> base = cloud_field(kN, kN, kN);
  const float tiny = std::ldexp(1.0f, -130);  // 2^-130: denormal in float32
  REQUIRE(std::fpclassify(tiny) == FP_SUBNORMAL);
  std::vector<float> denorm(base.size());
  for (std::size_t i = 0; i < base.size(); ++i) denorm[i] = base[i] * tiny;  // all denormal or 0
  SECTION("with range [0, 1]: u ~ 1e-39, no medium where opacity(0) = 0") {
    tessera::SceneDesc s = lit_cloud();
    s.tf.emission = tessera::ColorTF();
    const std::vector<float> zero(base.size(), 0.0f);
    tessera::RenderStats st;
    const tessera::Film a = render(view_of(denorm, tessera::DType::Float32), s, &st);
    CHECK(all_finite(a));
    CHECK(st.real_collisions == 0);
    CHECK(bit_identical(a, render(view_of(zero, tessera::DType::Float32), s)));
  }
  SECTION("with a denormal range: the same image as the unit-scale field, within noise") {
    tessera::SceneDesc s = lit_cloud();
    s.image.spp = 64;
    const tessera::Film unit = render(view_of(base, tessera::DType::Float32), s);
    s.tf.hi = tiny;
    s.options.seed = 901;  // independent samples
    tessera::RenderStats st;
    const tessera::Film small = render(view_of(denorm, tessera::DType::Float32), s, &st);
    CHECK(all_finite(small));
    CHECK(st.real_collisions > 0);
    const PixelTest t = compare_films(small, unit);
    INFO(t.describe());
    CHECK(t.ok());
    CHECK(std::fabs(t.mean_diff) < 3.0 * t.mean_diff_se);
  }
}

TEST_CASE("density_scale from 1e-8 to 1e8: transmittance per pixel", "[accuracy][stress]") {
  const std::vector<float> field = constant_field(3, 3, 3, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 3, 3, 3);
  for (const double sigma : {1e-8, 1e-4, 1.0, 1e4, 1e8}) {
    tessera::SceneDesc s = unit_box_scene(sigma, 0.0);
    s.geometry.spacing = Vec3(0.5);
    s.background.color = Color(1.0);
    s.camera.position = Vec3(2.0, -1.3, 1.9);
    s.camera.look_at = Vec3(0.5, 0.5, 0.5);
    s.camera.up = Vec3(0.0, 0.0, 1.0);
    s.camera.fov_deg = 42.0;
    s.image = {16, 16, 256, 0.0};
    s.options.seed = 910;
    tessera::RenderStats st;
    const PixelTest t = absorbing_box_test(view, s, Vec3(0.0), Vec3(1.0), sigma, 64, &st);
    INFO("sigma " << sigma << ": " << t.describe());
    CHECK(t.ok());
    CHECK(t.mean_z() < 4.0);
    CHECK(st.discarded_samples == 0);
  }
  // A scattering box at the extremes: finite, between 0 and the background (no light is
  // created), with single and multiple scattering.
  for (const double sigma : {1e-8, 1e8}) {
    for (const auto sc : {tessera::Scattering::Single, tessera::Scattering::Multiple}) {
      tessera::SceneDesc s = unit_box_scene(sigma, 0.9);
      s.geometry.spacing = Vec3(0.5);
      s.background.color = Color(1.0);
      s.integrator.scattering = sc;
      s.integrator.max_bounces = 64;
      s.camera.position = Vec3(2.0, 1.3, -1.9);
      s.camera.look_at = Vec3(0.5, 0.5, 0.5);
      s.image = {8, 8, 32, 0.0};
      tessera::RenderStats st;
      const tessera::Film f = render(view, s, &st);
      const ImageMean m = image_mean(f);
      INFO("scattering, sigma " << sigma << ": mean " << m.mean);
      CHECK(all_finite(f));
      CHECK(st.discarded_samples == 0);
      CHECK(m.mean <= 1.0 + 4.0 * m.se);
      CHECK(m.mean > 0.0);
    }
  }
}
