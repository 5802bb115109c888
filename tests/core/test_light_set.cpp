// Tests for the light set the kernels see (light_set.h) and the kernel scene prepare() makes
// (kernel_scene.h): every kind behind one interface, in the documented order, with the
// selection strategy's pmf; pdf() agrees with sample() through the set for every kind.
// Deterministic (fixed points and sample positions); no statistics.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "kernel/kernel_scene.h"
#include "light_lookup.h"
#include "lights/light_set.h"
#include "scene/prepared_scene_impl.h"
#include "test_support.h"

#include <cmath>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

using tessera::Color;
using tessera::Vec3;

namespace {

tessera::SceneDesc lit_scene() {
  tessera::SceneDesc s;
  s.tf.opacity = tessera::ScalarTF::constant(1.0);
  s.camera.position = Vec3(0.5, 0.5, 4.0);
  s.camera.look_at = Vec3(0.5);
  s.image = {16, 12, 1, 0.0};
  s.lights.push_back(tessera::SphereLightDesc{Vec3(3.0, 0.5, 0.5), 0.3, Color(2.0)});  // listed before the rect
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 3.0, 0.5), Vec3(0.5), 1.0, 0.5, Color(4.0)});
  s.background.color = Color(0.2, 0.3, 0.4);
  return s;
}

}  // namespace

TEST_CASE("kernel scene and light set are trivially copyable views", "[light_set][kernel_scene]") {
  STATIC_REQUIRE(std::is_trivially_copyable_v<tessera::KernelScene>);
  STATIC_REQUIRE(std::is_trivially_copyable_v<tessera::LightSet>);
  STATIC_REQUIRE(std::is_trivially_copyable_v<tessera::Light>);
}

// The central list of kinds (LightDesc) and the light set agree: one prepared kind per
// description kind, in the same order, then the background; each kind's prepared class is
// the one its LightKind names.
template <std::size_t... I>
constexpr bool kinds_agree(std::index_sequence<I...>) {
  return (std::is_same_v<std::variant_alternative_t<I, tessera::KernelLight>,
                         typename tessera::LightKind<std::variant_alternative_t<I, tessera::LightDesc>>::Kernel> &&
          ...);
}
static_assert(std::variant_size_v<tessera::KernelLight> == std::variant_size_v<tessera::LightDesc> + 1);
static_assert(kinds_agree(std::make_index_sequence<std::variant_size_v<tessera::LightDesc>>{}));
static_assert(std::is_same_v<std::variant_alternative_t<std::variant_size_v<tessera::LightDesc>, tessera::KernelLight>,
                             tessera::EnvironmentLight>);

TEST_CASE("the light set orders lights kind by kind, whatever the list's order", "[light_set]") {
  const std::vector<float> field = tessera_test::constant_field(4, 4, 4, 0.5f);
  const tessera::FieldView view = tessera::FieldView::contiguous(field.data(), tessera::DType::Float32, 4, 4, 4);
  tessera::SceneDesc s = lit_scene();
  s.lights.clear();
  s.lights.push_back(tessera::SphereLightDesc{Vec3(3.0, 0.5, 0.5), 0.3, Color(2.0)});
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 3.0, 0.5), Vec3(0.5), 1.0, 0.5, Color(4.0)});
  s.lights.push_back(tessera::SphereLightDesc{Vec3(0.5, -3.0, 0.5), 0.3, Color(6.0)});
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 0.5, -3.0), Vec3(0.5), 1.0, 1.0, Color(8.0)});
  CHECK(tessera::count_lights<tessera::RectLightDesc>(s.lights) == 2);
  CHECK(tessera::nth_light<tessera::SphereLightDesc>(s.lights, 1).radiance == Color(6.0));
  CHECK_THROWS_AS(tessera::nth_light<tessera::SphereLightDesc>(s.lights, 2), std::out_of_range);
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  const tessera::LightSet& L = prepared_scene_impl(ps).kernel.lights;
  REQUIRE(L.count() == 5);
  REQUIRE(L.area_count() == 4);
  // rects in list order (radiance 4 then 8), spheres in list order (2 then 6), background
  const Vec3 d(0.0, 1.0, 0.0);
  CHECK(L[0].radiance(d) == Color(4.0));
  CHECK(L[1].radiance(d) == Color(8.0));
  CHECK(L[2].radiance(d) == Color(2.0));
  CHECK(L[3].radiance(d) == Color(6.0));
  CHECK(L[4].infinite());
  // prepare() names a bad light by kind and its index within the kind
  std::get<tessera::SphereLightDesc>(s.lights[2]).center = Vec3(INFINITY);
  CHECK_THROWS_WITH(tessera::prepare(view, s), Catch::Contains("sphere light 1: position"));
}

TEST_CASE("prepare fills the kernel scene: rects, spheres, then the emitting background", "[light_set][kernel_scene]") {
  const std::vector<float> field = tessera_test::constant_field(4, 4, 4, 0.5f);
  const tessera::FieldView view = tessera::FieldView::contiguous(field.data(), tessera::DType::Float32, 4, 4, 4);
  tessera::SceneDesc s = lit_scene();
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  const tessera::KernelScene& ks = prepared_scene_impl(ps).kernel;
  CHECK(ks.width == 16);
  CHECK(ks.height == 12);
  CHECK(ks.tile_count == ps.tiles().size());
  CHECK(ks.tiles == ps.tiles().data());
  CHECK(ks.field.data == field.data());
  const tessera::LightSet& L = ks.lights;
  REQUIRE(L.count() == 3);
  REQUIRE(L.area_count() == 2);
  // Order: the rect (met at y = 3), the sphere (met at x = 2.7), the background (infinite)
  const tessera::Ray up{Vec3(0.5, 0.5, 0.5), Vec3(0.0, 1.0, 0.0)};
  const tessera::Ray east{Vec3(0.5, 0.5, 0.5), Vec3(1.0, 0.0, 0.0)};
  CHECK(L[0].intersect(up) == Approx(2.5));
  CHECK(L[0].intersect(east) < 0.0);
  CHECK(L[1].intersect(east) == Approx(2.2));
  CHECK(L[1].intersect(up) < 0.0);
  CHECK(L[2].infinite());
  CHECK(L[2].intersect(up) < 0.0);
  CHECK(L[0].radiance(up.d) == Color(4.0));
  CHECK(L[2].radiance(up.d) == Color(0.2, 0.3, 0.4));
  // Uniform selection: each light 1/3; pick covers every index in order
  for (int i = 0; i < 3; ++i) CHECK(L.sampler().pmf(i) == 1.0 / 3.0);
  CHECK(L.sampler().pick(0.0) == 0);
  CHECK(L.sampler().pick(0.34) == 1);
  CHECK(L.sampler().pick(0.67) == 2);
  CHECK(L.sampler().pick(std::nextafter(1.0, 0.0)) == 2);
  // A black background is not a light, but camera rays still see it
  s.background.color = Color(0.0);
  const tessera::PreparedScene dark = tessera::prepare(view, s);
  CHECK(prepared_scene_impl(dark).kernel.lights.count() == 2);
  CHECK(prepared_scene_impl(dark).kernel.lights.background_visible());
}

TEST_CASE("through the set, every kind's pdf() equals the pdf its sample() reports", "[light_set]") {
  const std::vector<float> field = tessera_test::constant_field(4, 4, 4, 0.5f);
  const tessera::FieldView view = tessera::FieldView::contiguous(field.data(), tessera::DType::Float32, 4, 4, 4);
  const tessera::PreparedScene ps = tessera::prepare(view, lit_scene());
  const tessera::LightSet& L = prepared_scene_impl(ps).kernel.lights;
  const Vec3 x(0.5, 0.6, 0.4);
  for (int i = 0; i < L.count(); ++i) {
    for (const auto& [u1, u2] : {std::pair{0.1, 0.2}, std::pair{0.5, 0.5}, std::pair{0.9, 0.7}}) {
      const tessera::LightSample s = L[i].sample(x, u1, u2);
      INFO("light " << i << " u " << u1 << " " << u2);
      REQUIRE(s.pdf > 0.0);
      CHECK(std::fabs(glm::length(s.wi) - 1.0) < 1e-12);
      CHECK(L[i].pdf(x, s.wi, s.dist) == Approx(s.pdf).epsilon(1e-9));
      if (!L[i].infinite()) {
        CHECK(L[i].intersect(tessera::Ray{x, s.wi}) == Approx(s.dist).epsilon(1e-9));
      } else {
        CHECK(std::isinf(s.dist));
      }
    }
  }
}
