// Empty-space reach (field/empty_reach.h) against a brute-force Chebyshev distance, and the
// macrocell walk's skips over it: the same non-empty segments as a walk without the table,
// and empty segments only where the field's extinction is 0.
#include <catch2/catch.hpp>

#include "field/empty_reach.h"
#include "field/majorant_grid.h"
#include "kernel/grid_medium.h"
#include "sampling/rng.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace {

/// Chebyshev distance from cell (x, y, z) to the nearest cell with majorant > 0, capped.
int brute_reach(const std::vector<double>& maj, const std::int64_t nc[3], std::int64_t x, std::int64_t y,
                std::int64_t z) {
  if (maj[static_cast<std::size_t>((z * nc[1] + y) * nc[0] + x)] > 0.0) return 0;
  int best = tessera::kMaxEmptyReach;
  for (std::int64_t k = 0; k < nc[2]; ++k)
    for (std::int64_t j = 0; j < nc[1]; ++j)
      for (std::int64_t i = 0; i < nc[0]; ++i)
        if (maj[static_cast<std::size_t>((k * nc[1] + j) * nc[0] + i)] > 0.0) {
          const auto d = std::max({std::llabs(i - x), std::llabs(j - y), std::llabs(k - z)});
          best = std::min<int>(best, static_cast<int>(d));
        }
  return best;
}

}  // namespace

TEST_CASE("empty reach is the capped Chebyshev distance to the nearest non-empty cell", "[empty_reach]") {
  tessera::Rng rng(7, 0, 0, 0);
  int checked = 0;
  for (int trial = 0; trial < 60; ++trial) {
    std::int64_t nc[3];
    for (int a = 0; a < 3; ++a) nc[a] = 1 + static_cast<std::int64_t>(rng.uniform() * 14.0);
    const double density = trial % 5 == 0 ? 0.0 : (trial % 5 == 1 ? 1.0 : rng.uniform() * 0.2);
    std::vector<double> maj(static_cast<std::size_t>(nc[0] * nc[1] * nc[2]));
    for (double& m : maj) m = rng.uniform() < density ? 0.5 : 0.0;
    std::vector<std::uint8_t> reach(maj.size(), 77);
    tessera::fill_empty_reach(maj.data(), nc, reach.data());
    for (std::int64_t z = 0; z < nc[2]; ++z)
      for (std::int64_t y = 0; y < nc[1]; ++y)
        for (std::int64_t x = 0; x < nc[0]; ++x) {
          const int want = brute_reach(maj, nc, x, y, z);
          const int got = reach[static_cast<std::size_t>((z * nc[1] + y) * nc[0] + x)];
          if (got != want) FAIL("cell " << x << "," << y << "," << z << ": reach " << got << ", want " << want);
          ++checked;
        }
  }
  CHECK(checked > 10000);
}

TEST_CASE("empty reach caps at 255 on a grid larger than the cap", "[empty_reach]") {
  const std::int64_t nc[3] = {600, 1, 1};
  std::vector<double> maj(600, 0.0);
  maj[0] = 1.0;
  std::vector<std::uint8_t> reach(600);
  tessera::fill_empty_reach(maj.data(), nc, reach.data());
  CHECK(reach[0] == 0);
  CHECK(reach[1] == 1);
  CHECK(reach[254] == 254);
  CHECK(reach[255] == 255);
  CHECK(reach[599] == 255);
}

TEST_CASE("the macrocell walk's empty skips keep every non-empty segment and skip only empty space",
          "[empty_reach][majorant_grid]") {
  // Sparse blobs in a 40^3 field, macrocells of 2: wide empty regions with reach >= 3
  constexpr int N = 40;
  std::vector<float> v(static_cast<std::size_t>(N) * N * N, 0.0f);
  tessera::Rng frng(3, 0, 0, 0);
  for (int b = 0; b < 4; ++b) {
    const double cx = 5 + 30 * frng.uniform(), cy = 5 + 30 * frng.uniform(), cz = 5 + 30 * frng.uniform();
    for (int z = 0; z < N; ++z)
      for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
          const double r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz);
          float& f = v[static_cast<std::size_t>((z * N + y) * N + x)];
          f = std::max(f, static_cast<float>(std::exp(-r2 / 8.0)));
        }
  }
  const tessera::FieldView view = tessera::FieldView::contiguous(v.data(), tessera::DType::Float32, N, N, N);
  tessera::TransferFunction tf;
  tf.lo = 0.0;
  tf.hi = 1.0;
  tf.density_scale = 3.0;
  tf.opacity = tessera::ScalarTF({0.0, 0.3, 1.0}, {0.0, 0.0, 1.0});
  tessera::MajorantGrid grid;
  grid.build(view, 2);
  grid.update(tf);
  auto with = tessera_test::make_medium<float>(view, tf, &grid);
  auto without = with;
  without.empty_reach = nullptr;
  tessera::Rng rng(11, 0, 0, 0);
  int skips = 0, bad = 0;
  for (int r = 0; r < 400; ++r) {
    tessera::Vec3 a, b;
    for (int ax = 0; ax < 3; ++ax) {
      a[ax] = (N - 1) * rng.uniform();
      b[ax] = (N - 1) * rng.uniform();
    }
    if (r % 4 == 1) b.y = a.y, b.z = a.z;  // along x
    const double len = glm::length(b - a);
    if (!(len > 1e-6)) continue;
    const tessera::Vec3 dv = (b - a) / len;
    struct Seg {
      double ta, tb, maj;
    };
    std::vector<Seg> s0, s1;
    double covered = 0.0;
    tessera::traverse_macrocells(without, a, dv, 0.0, len, [&](double ta, double tb, double maj) {
      if (maj > 0.0) s0.push_back({ta, tb, maj});
      return false;
    });
    tessera::traverse_macrocells(with, a, dv, 0.0, len, [&](double ta, double tb, double maj) {
      covered += tb - ta;
      if (maj > 0.0) {
        s1.push_back({ta, tb, maj});
      } else {
        const double cells = (tb - ta) / 2.0;
        if (cells > 1.8) ++skips;  // longer than any one cell: a skip
        for (int k = 0; k < 8; ++k) {
          const double t = ta + (tb - ta) * (k + 0.5) / 8.0;
          if (with.sigma_t(a + t * dv) != 0.0) ++bad;
        }
      }
      return false;
    });
    CHECK(std::fabs(covered - len) <= 1e-9 * (1.0 + len));
    REQUIRE(s0.size() == s1.size());
    for (std::size_t i = 0; i < s0.size(); ++i) {
      CHECK(s0[i].maj == s1[i].maj);
      CHECK(std::fabs(s0[i].ta - s1[i].ta) <= 1e-9 * (1.0 + len));
      CHECK(std::fabs(s0[i].tb - s1[i].tb) <= 1e-9 * (1.0 + len));
    }
  }
  CHECK(bad == 0);
  CHECK(skips > 100);
}
