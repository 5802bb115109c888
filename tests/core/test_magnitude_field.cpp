// A vector's magnitude read in place (magnitude_field.h): the image is bit-identical to that of
// a float64 array holding the magnitudes, whatever the components' dtypes and layouts
// (separate arrays, one interleaved array, mixed dtypes), on uniform and rectilinear axes, for
// vertex and cell data, and under any thread count; the summary equals the copy's; the
// majorants bound the magnitude (checked against the copy's summary, cell by cell); faults
// are named.
#include <tessera/magnitude_field.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "test_support.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

using tessera::DType;
using tessera::FieldView;
using tessera::MagnitudeField;
using tessera::Vec3;

namespace {

constexpr int NX = 13, NY = 11, NZ = 9;

/// Smooth components with a sign change (so |v| is not any one of them), at vertex (i, j, k).
double comp(int c, int i, int j, int k) {
  const double x = i / double(NX - 1), y = j / double(NY - 1), z = k / double(NZ - 1);
  if (c == 0) return std::sin(3.0 * x + 1.0) * std::cos(2.0 * y) - 0.2;
  if (c == 1) return 0.7 * (y - 0.5) + 0.3 * z * x;
  return std::exp(-4.0 * ((x - 0.4) * (x - 0.4) + (z - 0.6) * (z - 0.6))) - 0.1 * y;
}

/// The three components interleaved (x fastest; 3 floats per vertex), three separate arrays
/// of doubles, and the float64 copy of the magnitudes computed from the interleaved floats.
struct Vectors {
  std::vector<float> inter;
  std::vector<double> sep[3];
  std::vector<double> mag_inter;  ///< magnitude() of the interleaved floats
  std::vector<double> mag_mixed;  ///< magnitude() of (float u, double v, double w)
  Vectors() {
    inter.resize(3u * NX * NY * NZ);
    for (auto& s : sep) s.resize(std::size_t(NX) * NY * NZ);
    mag_inter.resize(sep[0].size());
    mag_mixed.resize(sep[0].size());
    for (int k = 0; k < NZ; ++k)
      for (int j = 0; j < NY; ++j)
        for (int i = 0; i < NX; ++i) {
          const std::size_t e = (std::size_t(k) * NY + j) * NX + i;
          for (int c = 0; c < 3; ++c) {
            inter[3 * e + c] = static_cast<float>(comp(c, i, j, k));
            sep[c][e] = comp(c, i, j, k);
          }
          mag_inter[e] = tessera::magnitude(inter[3 * e], inter[3 * e + 1], inter[3 * e + 2]);
          mag_mixed[e] = tessera::magnitude(inter[3 * e], sep[1][e], sep[2][e]);
        }
  }
  MagnitudeField interleaved() const {
    MagnitudeField m;
    for (int c = 0; c < 3; ++c) {
      m.components[c] = FieldView::contiguous(inter.data() + c, DType::Float32, NX, NY, NZ);
      for (int a = 0; a < 3; ++a) m.components[c].byte_strides[a] *= 3;
    }
    return m;
  }
  MagnitudeField mixed() const {
    MagnitudeField m = interleaved();
    for (int c = 1; c < 3; ++c) m.components[c] = FieldView::contiguous(sep[c].data(), DType::Float64, NX, NY, NZ);
    return m;
  }
};

tessera::SceneDesc scene(bool cell, const std::vector<double>* xs) {
  tessera::SceneDesc s;
  s.geometry.origin = Vec3(-0.6, -0.5, -0.4);
  s.geometry.spacing = Vec3(0.1);
  s.geometry.association = cell ? tessera::Association::Cell : tessera::Association::Vertex;
  if (xs) s.geometry.coords[0] = xs->data();
  s.tf.lo = 0.0;
  s.tf.hi = 1.2;
  s.tf.density_scale = 12.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.3, 1.0}, {0.0, 0.4, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {tessera::Color(0.9, 0.5, 0.2), tessera::Color(0.2, 0.6, 0.9)});
  s.camera.position = Vec3(1.2, 0.8, -2.5);
  s.camera.look_at = Vec3(0.0);
  s.camera.fov_deg = 40.0;
  s.lights.push_back(tessera::SphereLightDesc{Vec3(-2.0, 1.5, -1.0), 0.4, tessera::Color(4.0)});
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = tessera::Color(0.2, 0.25, 0.3);
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 4;
  s.integrator.macrocell = 4;
  s.image = {20, 14, 3};
  return s;
}

std::vector<tessera::PixelSums> pixels(const tessera::PreparedScene& ps) {
  return tessera_test::render_film(ps).pixels();
}

bool same(const std::vector<tessera::PixelSums>& a, const std::vector<tessera::PixelSums>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(tessera::PixelSums)) == 0;
}

}  // namespace

TEST_CASE("a vector's magnitude renders bit-identical to a float64 copy of it", "[magnitude]") {
  const Vectors v;
  std::vector<double> xs(NX + 1);
  for (int i = 0; i <= NX; ++i) xs[std::size_t(i)] = -0.6 + 0.1 * i + 0.004 * i * i;
  for (const bool cell : {false, true})
    for (const bool rect : {false, true}) {
      CAPTURE(cell, rect);
      std::vector<double> axis(xs.begin(), xs.begin() + (cell ? NX + 1 : NX));
      tessera::SceneDesc s = scene(cell, rect ? &axis : nullptr);
      const FieldView copy = FieldView::contiguous(v.mag_inter.data(), DType::Float64, NX, NY, NZ);
      const auto expected = pixels(tessera::prepare(copy, s));
      CHECK(same(pixels(tessera::prepare(v.interleaved(), s)), expected));
      s.options.threads = 1;
      s.options.tile = 5;
      CHECK(same(pixels(tessera::prepare(v.interleaved(), s)), expected));
      const FieldView mixed_copy = FieldView::contiguous(v.mag_mixed.data(), DType::Float64, NX, NY, NZ);
      CHECK(same(pixels(tessera::prepare(v.mixed(), s)), pixels(tessera::prepare(mixed_copy, s))));
    }
}

TEST_CASE("a magnitude's summary is the summary of its float64 copy", "[magnitude]") {
  const Vectors v;
  const FieldView copy = FieldView::contiguous(v.mag_inter.data(), DType::Float64, NX, NY, NZ);
  for (const int edge : {1, 4, 64}) {
    const auto m = tessera::magnitude_summary(v.interleaved(), edge);
    const auto c = tessera::FieldSummary::build(copy, edge);
    REQUIRE(m->cell_count() == c->cell_count());
    CHECK(m->value_min() == c->value_min());
    CHECK(m->value_max() == c->value_max());
    CHECK(m->nan_vertices() == c->nan_vertices());
    for (std::int64_t i = 0; i < m->cell_count(); ++i) {
      CHECK(m->ranges()[std::size_t(i)].lo == c->ranges()[std::size_t(i)].lo);
      CHECK(m->ranges()[std::size_t(i)].hi == c->ranges()[std::size_t(i)].hi);
    }
    CHECK(m->layout().dtype == DType::Float64);
  }
  // The smallest magnitude is no component's value: the norm is taken, not a component
  double lo = 1e300;
  for (double x : v.mag_inter) lo = std::min(lo, x);
  CHECK(tessera::magnitude_summary(v.interleaved(), 4)->value_min() == lo);
}

TEST_CASE("magnitude(): NaN and infinite components", "[magnitude]") {
  CHECK(tessera::magnitude(3.0, 4.0, 0.0) == 5.0);
  CHECK(std::isnan(tessera::magnitude(NAN, 1.0, 1.0)));
  CHECK(tessera::magnitude(-INFINITY, 1.0, 1.0) == INFINITY);
  CHECK(tessera::magnitude(1e200, 1e200, 0.0) == INFINITY);  // the sum overflows
  // A vector field with NaN and overflowing components still renders, finitely
  std::vector<float> u(std::size_t(NX) * NY * NZ, 0.5f), w(u.size(), 0.25f);
  std::vector<double> big(u.size(), 1e200);
  u[17] = NAN;
  MagnitudeField m;
  m.components[0] = FieldView::contiguous(u.data(), DType::Float32, NX, NY, NZ);
  m.components[1] = FieldView::contiguous(big.data(), DType::Float64, NX, NY, NZ);
  m.components[2] = FieldView::contiguous(w.data(), DType::Float32, NX, NY, NZ);
  const auto summary = tessera::magnitude_summary(m, 4);
  CHECK(summary->nan_vertices() == 1);
  CHECK_FALSE(summary->has_finite());
  const tessera::Film film = tessera_test::render_film(tessera::prepare(m, scene(false, nullptr)));
  for (const tessera::PixelSums& p : film.pixels()) CHECK(std::isfinite(p.r + p.g + p.b + p.a));
}

TEST_CASE("a magnitude's faults are named", "[magnitude]") {
  const Vectors v;
  MagnitudeField m = v.mixed();
  m.components[2].dims[1] = NY - 1;
  CHECK_THROWS_WITH(tessera::prepare(m, scene(false, nullptr)),
                    Catch::Contains("component 2 has 13x10x9 elements, component 0 13x11x9"));
  m = v.mixed();
  m.components[1].data = nullptr;
  CHECK_THROWS_WITH(tessera::prepare(m, scene(false, nullptr)), Catch::Contains("component 1: data pointer is null"));
  m = v.mixed();
  const auto wrong_edge = tessera::magnitude_summary(m, 1);
  CHECK_THROWS_WITH(tessera::prepare(m, scene(false, nullptr), wrong_edge),
                    Catch::Contains("the field summary has macrocell edge 1, this scene needs 4"));
}
