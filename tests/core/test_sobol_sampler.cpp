// Tests for the low-discrepancy sampler (sobol_sampler.h, owen_scramble.h): the Owen scramble
// keeps each value's leading digits a function of the leading digits only; every aligned block
// of 2^k samples of one pixel and dimension pair is a (0,k,2)-net; distinct pairs and pixels
// are decorrelated; each value is uniform across pixels; the sampler is a pure function of
// its keys, and without it the helpers draw the Rng in order.
//
// Statistics: correlations within 5 standard errors (1/sqrt(n)), a chi-square test at
// significance 1e-4 (Wilson-Hilferty critical value). Fixed seeds.
#include <catch2/catch.hpp>

#include "sampling/owen_scramble.h"
#include "sampling/rng.h"
#include "sampling/sobol_sampler.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

using tessera::Rng;
using tessera::Sample2;
using tessera::SampleDim;
using tessera::SobolSampler;

namespace {
constexpr SampleDim kPairs[] = {SampleDim::Pixel, SampleDim::Lens, SampleDim::LightUv, SampleDim::Direction};
constexpr SampleDim kSingles[] = {SampleDim::LightPick, SampleDim::ScatterChoice, SampleDim::Lobe};

/// True if the 2^k points are one per box of every 2^-a x 2^-(k-a) partition of [0,1)^2.
bool is_02_net(const std::vector<Sample2>& p, int k) {
  const std::size_t n = std::size_t{1} << k;
  if (p.size() != n) return false;
  for (int a = 0; a <= k; ++a) {
    std::vector<int> count(n, 0);
    for (const Sample2& s : p) {
      const auto bx = static_cast<std::size_t>(s.x * static_cast<double>(1u << a));
      const auto by = static_cast<std::size_t>(s.y * static_cast<double>(1u << (k - a)));
      if (++count[(bx << (k - a)) | by] > 1) return false;
    }
  }
  return true;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sa += a[i];
    sb += b[i];
    saa += a[i] * a[i];
    sbb += b[i] * b[i];
    sab += a[i] * b[i];
  }
  const double cov = sab / n - sa / n * sb / n;
  return cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
}
}  // namespace

TEST_CASE("Owen scrambling keeps leading digits a function of leading digits", "[sampling][sobol]") {
  Rng rng(21, 0, 0, 0);
  std::set<std::uint32_t> images;
  for (int t = 0; t < 2000; ++t) {
    const auto x = static_cast<std::uint32_t>(rng.next_u64());
    const auto seed = static_cast<std::uint32_t>(rng.next_u64());
    const int k = static_cast<int>(rng.next_u64() % 32) + 1;
    const std::uint32_t top = k == 32 ? ~0u : ~(~0u >> k);  // the leading k digits
    // Any x' with the same leading k digits scrambles to the same leading k digits
    const std::uint32_t y = (x & top) | (static_cast<std::uint32_t>(rng.next_u64()) & ~top);
    CHECK((tessera::owen_scramble(x, seed) & top) == (tessera::owen_scramble(y, seed) & top));
    images.insert(tessera::owen_scramble(static_cast<std::uint32_t>(t), 12345u));
  }
  CHECK(images.size() == 2000);  // a bijection: distinct inputs, distinct outputs
  CHECK(tessera::reverse_bits32(1u) == 0x80000000u);
  CHECK(tessera::reverse_bits32(0x12345678u) == 0x1E6A2C48u);
}

TEST_CASE("Sobol' second dimension: the first points", "[sampling][sobol]") {
  const double expect[] = {0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};  // index order, not Gray code
  for (std::uint32_t i = 0; i < 8; ++i) CHECK(SobolSampler::sobol_dim1(i) * 0x1.0p-32 == expect[i]);
}

TEST_CASE("every aligned block of 2^k samples of a pair is a (0,k,2)-net", "[sampling][sobol]") {
  for (std::uint64_t pixel : {0ull, 1ull, 77777ull}) {
    for (std::uint64_t seed : {0ull, 3ull}) {
      for (SampleDim d : kPairs) {
        for (int k = 0; k <= 10; ++k) {
          for (std::uint64_t block : {0ull, 1ull, 5ull}) {
            std::vector<Sample2> p;
            const std::uint64_t n = 1ull << k;
            for (std::uint64_t i = block * n; i < (block + 1) * n; ++i)
              p.push_back(SobolSampler(seed, 2, pixel, i).get_2d(d));
            INFO("pixel " << pixel << " seed " << seed << " dim " << static_cast<int>(d) << " k " << k);
            CHECK(is_02_net(p, k));
          }
        }
      }
      for (SampleDim d : kSingles) {  // 1D: one point per interval of 2^-k
        std::vector<int> count(256, 0);
        for (std::uint64_t i = 0; i < 256; ++i)
          ++count[static_cast<std::size_t>(SobolSampler(seed, 2, pixel, i).get_1d(d) * 256.0)];
        CHECK(std::count(count.begin(), count.end(), 1) == 256);
      }
    }
  }
}

TEST_CASE("distinct dimensions and pixels are decorrelated", "[sampling][sobol]") {
  constexpr int n = 4096;
  const double bound = 5.0 / std::sqrt(static_cast<double>(n));
  // Across the samples of one pixel: every pair of coordinates of distinct dimensions
  std::vector<std::vector<double>> c;
  for (SampleDim d : kPairs) {
    std::vector<double> x, y;
    for (int i = 0; i < n; ++i) {
      const Sample2 s = SobolSampler(9, 0, 42, static_cast<std::uint64_t>(i)).get_2d(d);
      x.push_back(s.x);
      y.push_back(s.y);
    }
    c.push_back(x);
    c.push_back(y);
  }
  for (SampleDim d : kSingles) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(SobolSampler(9, 0, 42, static_cast<std::uint64_t>(i)).get_1d(d));
    c.push_back(v);
  }
  for (std::size_t a = 0; a < c.size(); ++a)
    for (std::size_t b = a + 2 - a % 2; b < c.size(); ++b) {  // skip the two halves of one pair (the net)
      INFO("columns " << a << " and " << b);
      CHECK(std::fabs(correlation(c[a], c[b])) < bound);
    }
  // Sample 0 of neighbouring pixels, and of consecutive frames
  std::vector<double> p0, p1, f1;
  for (int i = 0; i < n; ++i) {
    const auto px = static_cast<std::uint64_t>(i);
    p0.push_back(SobolSampler(9, 0, px, 0).get_2d(SampleDim::Pixel).x);
    p1.push_back(SobolSampler(9, 0, px + 1, 0).get_2d(SampleDim::Pixel).x);
    f1.push_back(SobolSampler(9, 1, px, 0).get_2d(SampleDim::Pixel).x);
  }
  CHECK(std::fabs(correlation(p0, p1)) < bound);
  CHECK(std::fabs(correlation(p0, f1)) < bound);
}

TEST_CASE("each sampler value is uniform in the unit interval across pixels", "[sampling][sobol]") {
  // Chi-square over 64 bins of sample 3's light-sample u in 2^16 pixels, significance 1e-4
  constexpr int bins = 64, n = 1 << 16;
  std::vector<double> count(bins, 0.0);
  bool in_range = true;
  for (int p = 0; p < n; ++p) {
    const double u = SobolSampler(4, 0, static_cast<std::uint64_t>(p), 3).get_2d(SampleDim::LightUv).x;
    in_range = in_range && u >= 0.0 && u < 1.0;
    count[static_cast<std::size_t>(u * bins)] += 1.0;
  }
  const double e = static_cast<double>(n) / bins;
  double chi2 = 0.0;
  for (double c : count) chi2 += (c - e) * (c - e) / e;
  const double k = bins - 1, z = 3.719;  // Wilson-Hilferty, upper 1e-4 quantile
  const double crit = k * std::pow(1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k)), 3.0);
  CHECK(in_range);
  CHECK(chi2 < crit);
}

TEST_CASE("the sampler is a pure function of its keys, and without it the Rng is drawn in order", "[sampling][sobol]") {
  const auto v = [](std::uint64_t s, std::uint64_t f, std::uint64_t p, std::uint64_t i) {
    const Sample2 a = SobolSampler(s, f, p, i).get_2d(SampleDim::Direction);
    return std::vector<double>{a.x, a.y, SobolSampler(s, f, p, i).get_1d(SampleDim::Lobe)};
  };
  CHECK(v(1, 2, 3, 4) == v(1, 2, 3, 4));
  const std::set<std::vector<double>> distinct = {v(1, 2, 3, 4), v(2, 2, 3, 4), v(1, 3, 3, 4),
                                                  v(1, 2, 4, 4), v(1, 2, 3, 5), v(1, 2, 3, 4 + (1ull << 32))};
  CHECK(distinct.size() == 6);  // the index's upper half keys a fresh scramble
  Rng a(1, 2, 3, 4), b(1, 2, 3, 4);
  const Sample2 s = tessera::sample_2d(nullptr, SampleDim::Pixel, a);
  const double u = tessera::sample_1d(nullptr, SampleDim::Lobe, a);
  CHECK(s.x == b.uniform());
  CHECK(s.y == b.uniform());
  CHECK(u == b.uniform());
}
