// suspect_axis_order: dims given in the wrong order are caught, right ones never flagged.
#include <tessera/axis_order_check.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

using namespace tessera;

namespace {

/// A smooth field on nx x ny x nz, x fastest (as a raw file holds it).
std::vector<float> smooth(int nx, int ny, int nz) {
  std::vector<float> v;
  v.reserve(std::size_t(nx) * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        v.push_back(float(std::sin(0.21 * i) * std::cos(0.17 * j) + 0.5 * std::sin(0.13 * k + 0.3 * i / nx)));
  return v;
}

FieldView view(const std::vector<float>& v, std::int64_t nx, std::int64_t ny, std::int64_t nz) {
  return FieldView::contiguous(v.data(), DType::Float32, nx, ny, nz);
}

}  // namespace

TEST_CASE("axis order: a smooth field read with its own dims is not suspected", "[axis_order]") {
  const auto v = smooth(40, 24, 12);
  CHECK_FALSE(suspect_axis_order(view(v, 40, 24, 12)));
}

TEST_CASE("axis order: the same bytes read with reversed dims are suspected and the order named", "[axis_order]") {
  const auto v = smooth(40, 24, 12);
  const auto s = suspect_axis_order(view(v, 12, 24, 40));
  REQUIRE(s);
  CHECK(s->better == std::array<std::int64_t, 3>{40, 24, 12});
  CHECK(s->given == std::array<std::int64_t, 3>{12, 24, 40});
  const std::string w = axis_order_warning(*s, "volume.dims");
  CHECK(w.find("volume.dims [12, 24, 40] may be in the wrong order") != std::string::npos);
  CHECK(w.find("dims [40, 24, 12] make the data smooth") != std::string::npos);
}

TEST_CASE("axis order: swapping only the two slow axes is caught too", "[axis_order]") {
  const auto v = smooth(20, 30, 50);
  const auto s = suspect_axis_order(view(v, 20, 50, 30));
  REQUIRE(s);
  CHECK(s->better == std::array<std::int64_t, 3>{20, 30, 50});
}

TEST_CASE("axis order: noise, constants, NaN and cubes give no suspicion", "[axis_order]") {
  std::vector<float> noise(30 * 20 * 10);
  std::uint32_t x = 12345;
  for (float& f : noise) f = float((x = x * 1664525u + 1013904223u) >> 8) / float(1 << 24);
  CHECK_FALSE(suspect_axis_order(view(noise, 30, 20, 10)));
  CHECK_FALSE(suspect_axis_order(view(noise, 10, 20, 30)));

  const std::vector<float> constant(30 * 20 * 10, 2.5f);
  CHECK_FALSE(suspect_axis_order(view(constant, 10, 20, 30)));

  const std::vector<float> nan(30 * 20 * 10, std::nanf(""));
  CHECK_FALSE(suspect_axis_order(view(nan, 10, 20, 30)));

  const auto cube = smooth(16, 16, 16);
  CHECK_FALSE(suspect_axis_order(view(cube, 16, 16, 16)));
}

TEST_CASE("axis order: integer dtypes and a thin slab", "[axis_order]") {
  // uint8 ramp along x on 64 x 8 x 2: right dims smooth; read as 2 x 8 x 64 it jumps
  std::vector<std::uint8_t> v;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 64; ++i) v.push_back(std::uint8_t(i * 3 + j));
  CHECK_FALSE(suspect_axis_order(FieldView::contiguous(v.data(), DType::UInt8, 64, 8, 2)));
  const auto s = suspect_axis_order(FieldView::contiguous(v.data(), DType::UInt8, 2, 8, 64));
  REQUIRE(s);
  CHECK(s->better[0] == 64);
}
