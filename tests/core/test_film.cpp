// Tests for Film::resolve: pixel value = mean of its samples (docs/physics.md "Accumulation
// and output": after 1e5 samples within 1e-6 relative of the exact mean), variance of the
// mean from the luminance sums, empty pixels black with alpha 0.
#include <tessera/film.h>

#include <catch2/catch.hpp>

#include "sampling/rng.h"

#include <cmath>
#include <vector>

TEST_CASE("film resolves means, variance of the mean and counts", "[film]") {
  tessera::Film film(3, 2);
  // Pixel (1, 0): samples 1, 2, 3, 6 on every channel, alpha 1, 0, 1, 1
  const double xs[] = {1.0, 2.0, 3.0, 6.0};
  const double as[] = {1.0, 0.0, 1.0, 1.0};
  tessera::PixelSums& p = film.at(1, 0);
  for (int i = 0; i < 4; ++i) {
    p.r += xs[i];
    p.g += 2.0 * xs[i];
    p.b += 3.0 * xs[i];
    p.a += as[i];
    p.lum += xs[i];
    p.lum2 += xs[i] * xs[i];
    ++p.n;
    ++p.drawn;
  }
  const tessera::Image img = film.resolve();
  REQUIRE(img.width == 3);
  REQUIRE(img.height == 2);
  CHECK(img.px(1, 0)[0] == 3.0f);
  CHECK(img.px(1, 0)[1] == 6.0f);
  CHECK(img.px(1, 0)[2] == 9.0f);
  CHECK(img.px(1, 0)[3] == 0.75f);
  // sample variance of {1, 2, 3, 6} = 14/3, over n = 4
  CHECK(img.variance[1] == Approx(14.0 / 3.0 / 4.0).epsilon(1e-6));
  CHECK(img.samples[1] == 4.0f);
  // Untouched pixels: black, alpha 0, no samples
  for (const int i : {0, 2, 3, 4, 5}) {
    CHECK(img.rgba[4 * i + 0] == 0.0f);
    CHECK(img.rgba[4 * i + 3] == 0.0f);
    CHECK(img.samples[i] == 0.0f);
    CHECK(img.variance[i] == 0.0f);
  }
  const tessera::Image bare = film.resolve(false, false);
  CHECK(bare.variance.empty());
  CHECK(bare.samples.empty());
  film.clear();
  CHECK(film.at(1, 0).n == 0);
  CHECK_THROWS(tessera::Film(0, 4));
}

TEST_CASE("1e5 accumulated samples keep the mean within 1e-6 relative", "[film]") {
  tessera::Film film(1, 1);
  tessera::Rng rng(71, 0, 0, 0);
  long double exact = 0.0L;
  constexpr int n = 100000;
  for (int i = 0; i < n; ++i) {
    // Values spanning several orders of magnitude around 1e3
    const double v = 1e3 * std::exp(6.0 * rng.uniform() - 3.0);
    tessera::PixelSums& p = film.at(0, 0);
    p.r += v;
    p.lum += v;
    p.lum2 += v * v;
    ++p.n;
    exact += static_cast<long double>(v);
  }
  const double want = static_cast<double>(exact / n);
  const tessera::Image img = film.resolve();
  CHECK(std::fabs(img.rgba[0] - want) / want < 1e-6);
}
