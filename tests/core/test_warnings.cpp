// Warnings that explain an empty or odd image (scene_warnings.h): what the data's range, NaN
// count and bounds say against the transfer function and camera, and a render with no real
// collision naming its likely cause. A warning never changes the image.
#include <tessera/scene_warnings.h>

#include "test_support.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using Catch::Matchers::Contains;
using tessera::FieldView;
using tessera::Vec3;

namespace {

constexpr int N = 12;

/// Values in [-1.5, 1.5] (exactly: 1.5 * sin over a grid that reaches +-1 at its ends).
std::vector<float> wave() {
  std::vector<float> v(N * N * N);
  for (int k = 0; k < N; ++k)
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i)
        v[i + N * (j + N * k)] = i == 0 ? -1.5f : (i == N - 1 ? 1.5f : float(1.5 * std::sin(0.5 * i + j + k)));
  return v;
}

tessera::SceneDesc scene(double lo, double hi) {
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (N - 1));
  s.tf.lo = lo;
  s.tf.hi = hi;
  s.tf.density_scale = 30.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  s.camera.position = Vec3(0.5, 0.5, -2.0);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.image = {16, 16, 4, 0.0};
  return s;
}

struct Outcome {
  std::vector<std::string> warnings;
  tessera::RenderStats stats;
  std::vector<float> rgba;
};

Outcome run(const std::vector<float>& field, const tessera::SceneDesc& s) {
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, N, N, N);
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  Outcome o;
  const tessera::Film film = tessera_test::render_film(ps, &o.stats);
  o.warnings = tessera::render_warnings(ps, o.stats);
  o.rgba = film.resolve(false, false).rgba;
  return o;
}

}  // namespace

TEST_CASE("warnings: a visible field says nothing", "[warnings]") {
  const Outcome o = run(wave(), scene(-1.5, 1.5));
  CHECK(o.stats.real_collisions > 0);
  CHECK(o.warnings.empty());
}

TEST_CASE("warnings: transfer-function range disjoint from the data names both", "[warnings]") {
  const Outcome o = run(wave(), scene(10.0, 20.0));
  CHECK(o.stats.real_collisions == 0);
  REQUIRE(o.warnings.size() == 2);
  CHECK_THAT(o.warnings[0], Contains("transfer_function.range [10, 20] misses the data's values [-1.5, 1.5]: "
                                     "nothing of the field is visible"));
  CHECK_THAT(o.warnings[1], Contains("0 real collisions in " + std::to_string(o.stats.samples) + " samples"));
  CHECK_THAT(o.warnings[1], Contains("likely cause: transfer_function.range"));
}

TEST_CASE("warnings: disjoint range whose end has opacity shows a uniform block", "[warnings]") {
  tessera::SceneDesc s = scene(-20.0, -10.0);  // every value maps to u = 1, opacity 1
  const Outcome o = run(wave(), s);
  CHECK(o.stats.real_collisions > 0);
  REQUIRE(o.warnings.size() == 1);
  CHECK_THAT(o.warnings[0], Contains("misses the data's values [-1.5, 1.5]") && Contains("uniform block"));
}

TEST_CASE("warnings: opacity 0 over the whole data range", "[warnings]") {
  tessera::SceneDesc s = scene(-1.5, 3.0);
  s.tf.opacity = tessera::ScalarTF({0.0, 0.7, 1.0}, {0.0, 0.0, 1.0});  // u <= 0.667 for the data
  const Outcome o = run(wave(), s);
  CHECK(o.stats.real_collisions == 0);
  REQUIRE(o.warnings.size() == 2);
  CHECK_THAT(o.warnings[0], Contains("opacity transfer function is 0 over the data's values [-1.5, 1.5]"));
  CHECK_THAT(o.warnings[1], Contains("likely cause: the opacity transfer function"));
}

TEST_CASE("warnings: a constant field names its value", "[warnings]") {
  const std::vector<float> field(N * N * N, 300.0f);
  const Outcome o = run(field, scene(299.0, 301.0));
  REQUIRE_FALSE(o.warnings.empty());
  CHECK_THAT(o.warnings[0], Contains("the field is constant (300)"));
}

TEST_CASE("warnings: NaN vertices are counted", "[warnings]") {
  std::vector<float> field = wave();
  for (std::size_t i = 5; i < field.size(); i += 100) field[i] = std::numeric_limits<float>::quiet_NaN();
  const std::size_t nans = (field.size() - 5 + 99) / 100;
  const Outcome o = run(field, scene(-1.5, 1.5));
  REQUIRE(o.warnings.size() == 1);
  CHECK_THAT(o.warnings[0], Contains(std::to_string(nans) + " of " + std::to_string(N * N * N) + " vertices"));
  CHECK_THAT(o.warnings[0], Contains("NaN"));
}

TEST_CASE("warnings: a camera looking away, or a thin volume, is named as the cause", "[warnings]") {
  tessera::SceneDesc s = scene(-1.5, 1.5);
  s.camera.look_at = Vec3(0.5, 0.5, -5.0);  // the data is behind the camera
  Outcome o = run(wave(), s);
  CHECK(o.stats.real_collisions == 0);
  REQUIRE(o.warnings.size() == 2);
  CHECK_THAT(o.warnings[0], Contains("behind the camera"));
  CHECK_THAT(o.warnings[1], Contains("likely cause: the camera does not see the data"));

  s = scene(-1.5, 1.5);
  s.camera.position = Vec3(0.5, 0.5, -5.0);
  s.camera.look_at = Vec3(10.5, 0.5, 5.0);  // 45 degrees off the data: in front, outside a 30-degree view
  o = run(wave(), s);
  REQUIRE_FALSE(o.warnings.empty());
  CHECK_THAT(o.warnings[0], Contains("outside the camera's view"));
  CHECK(o.stats.real_collisions == 0);

  s = scene(-1.5, 1.5);
  s.tf.density_scale = 1e-12;
  o = run(wave(), s);
  CHECK(o.stats.real_collisions == 0);
  REQUIRE(o.warnings.size() == 1);
  CHECK_THAT(o.warnings[0], Contains("likely cause: transfer_function.density_scale too small"));
}

TEST_CASE("warnings: deciding them changes nothing in the image", "[warnings]") {
  const std::vector<float> field = wave();
  const tessera::SceneDesc s = scene(10.0, 20.0);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, N, N, N);
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  const tessera::Film a = tessera_test::render_film(ps);
  CHECK_FALSE(tessera::scene_warnings(ps).empty());
  const tessera::Film b = tessera_test::render_film(ps);
  CHECK(a.resolve(false, false).rgba == b.resolve(false, false).rgba);
}
