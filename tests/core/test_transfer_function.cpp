// Tests for the piecewise-linear transfer functions: interpolation, clamping, steps, the
// exact max_over() the majorants rely on, normalisation of field values, and input checks.
#include <tessera/transfer_function.h>

#include <catch2/catch.hpp>

#include "sampling/rng.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

using tessera::Color;
using tessera::ColorTF;
using tessera::ScalarTF;

TEST_CASE("scalar TF: linear between points, clamped at the ends, empty is zero", "[transfer_function]") {
  const ScalarTF tf({0.2, 0.6, 1.0}, {1.0, 3.0, 2.0});
  CHECK(tf.eval(-5.0) == 1.0);
  CHECK(tf.eval(0.2) == 1.0);
  CHECK(tf.eval(0.4) == Approx(2.0).epsilon(1e-15));
  CHECK(tf.eval(0.6) == 3.0);
  CHECK(tf.eval(0.8) == Approx(2.5).epsilon(1e-15));
  CHECK(tf.eval(7.0) == 2.0);
  CHECK(tf.max_value() == 3.0);
  CHECK_FALSE(tf.is_zero());
  CHECK(ScalarTF().eval(0.5) == 0.0);
  CHECK(ScalarTF().is_zero());
  CHECK(ScalarTF::constant(0.7).eval(0.1) == 0.7);
  CHECK(ScalarTF({0.0, 1.0}, {0.0, 0.0}).is_zero());
}

TEST_CASE("scalar TF steps: equal x jumps, the right value holds from the step on", "[transfer_function]") {
  const ScalarTF tf({0.0, 0.5, 0.5, 1.0}, {0.0, 1.0, 4.0, 4.0});
  CHECK(tf.eval(0.25) == Approx(0.5));
  CHECK(tf.eval(0.5) == 4.0);
  CHECK(tf.eval(std::nextafter(0.5, 0.0)) == Approx(1.0));
  CHECK(tf.max_over(0.0, 0.49) == Approx(0.98));
  CHECK(tf.max_over(0.0, 0.5) == 4.0);
}

TEST_CASE("max_over is an upper bound of the TF over the interval and attained", "[transfer_function]") {
  tessera::Rng rng(61, 0, 0, 0);
  int not_bound = 0, not_tight = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int np = 1 + static_cast<int>(rng.uniform() * 10.0);
    std::vector<double> xs(np), vs(np);
    for (int i = 0; i < np; ++i) xs[i] = 1.4 * rng.uniform() - 0.2, vs[i] = rng.uniform();
    std::sort(xs.begin(), xs.end());
    const ScalarTF tf(xs, vs);
    for (int q = 0; q < 20; ++q) {
      double u0 = 1.2 * rng.uniform() - 0.1, u1 = 1.2 * rng.uniform() - 0.1;
      if (u0 > u1) std::swap(u0, u1);
      if (q == 0) u1 = u0;  // a point
      const double m = tf.max_over(u0, u1);
      double dense = std::fmax(tf.eval(u0), tf.eval(u1));
      for (int k = 0; k <= 2000; ++k) dense = std::fmax(dense, tf.eval(std::min(u1, u0 + (u1 - u0) * k / 2000.0)));
      for (int i = 0; i < np; ++i)
        if (xs[i] >= u0 && xs[i] <= u1) dense = std::fmax(dense, tf.eval(xs[i]));
      if (dense > m) ++not_bound;
      if (m > dense + 1e-12) ++not_tight;
    }
  }
  CHECK(not_bound == 0);
  CHECK(not_tight == 0);
}

TEST_CASE("colour TF interpolates per channel", "[transfer_function]") {
  const ColorTF tf({0.0, 1.0}, {Color(0.0, 1.0, 2.0), Color(1.0, 1.0, 0.0)});
  const Color c = tf.eval(0.25);
  CHECK(c.x == Approx(0.25));
  CHECK(c.y == Approx(1.0));
  CHECK(c.z == Approx(1.5));
  CHECK(ColorTF().is_zero());
  CHECK(tessera::is_black(ColorTF().eval(0.3)));
}

TEST_CASE("normalise maps the range to [0, 1], clamps, and sends NaN to 0", "[transfer_function]") {
  tessera::TransferFunction tf;
  tf.lo = -2.0;
  tf.hi = 6.0;
  CHECK(tf.normalise(-2.0) == 0.0);
  CHECK(tf.normalise(2.0) == 0.5);
  CHECK(tf.normalise(6.0) == 1.0);
  CHECK(tf.normalise(-100.0) == 0.0);
  CHECK(tf.normalise(100.0) == 1.0);
  CHECK(tf.normalise(std::numeric_limits<double>::quiet_NaN()) == 0.0);
  CHECK(tf.normalise(std::numeric_limits<double>::infinity()) == 1.0);
  CHECK(tf.normalise(-std::numeric_limits<double>::infinity()) == 0.0);
}

TEST_CASE("TF construction rejects bad points naming them", "[transfer_function]") {
  CHECK_THROWS_WITH(ScalarTF({0.5, 0.2}, {1.0, 1.0}), Catch::Contains("point 1") && Catch::Contains("decreasing"));
  CHECK_THROWS_WITH(ScalarTF({0.0, 1.0}, {1.0}), Catch::Contains("counts differ"));
  CHECK_THROWS_WITH(ScalarTF({0.0, std::nan("")}, {1.0, 1.0}), Catch::Contains("not finite"));
  CHECK_THROWS_WITH(ScalarTF({0.0}, {std::numeric_limits<double>::infinity()}), Catch::Contains("not finite"));
  std::vector<double> many(tessera::kMaxTfPoints + 1, 0.5);
  CHECK_THROWS_WITH(ScalarTF(many, many), Catch::Contains("at most"));
  CHECK_THROWS_WITH(ColorTF({0.0}, {Color(std::nan(""))}), Catch::Contains("not finite"));
}

TEST_CASE("ScalarTF's segment table gives tf_eval's value bit for bit", "[tf]") {
  // Random TFs with steps (equal x), points outside [0, 1] and several points per bin
  tessera::Rng rng(99, 0, 0, 0);
  int mismatches = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + static_cast<int>(rng.uniform() * 40.0);
    std::vector<double> xs(static_cast<std::size_t>(n)), vs(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      xs[static_cast<std::size_t>(i)] = trial % 3 == 0 ? -0.2 + 1.4 * rng.uniform() : rng.uniform() * 0.05 + 0.5;
      vs[static_cast<std::size_t>(i)] = rng.uniform();
    }
    std::sort(xs.begin(), xs.end());
    if (n > 3) xs[2] = xs[1];  // a step
    const tessera::ScalarTF tf(xs, vs);
    for (int k = 0; k < 2000; ++k) {
      const double u = k % 10 == 0 ? xs[static_cast<std::size_t>(k / 10) % xs.size()] : -0.1 + 1.2 * rng.uniform();
      const double a = tf.eval(u), b = tessera::detail::tf_eval(xs.data(), vs.data(), n, u);
      if (std::memcmp(&a, &b, sizeof a) != 0) ++mismatches;
    }
  }
  CHECK(mismatches == 0);
}
