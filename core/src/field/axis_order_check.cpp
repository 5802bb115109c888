#include <tessera/axis_order_check.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tessera {
namespace {

/// splitmix64: a fixed, portable stream of sample positions.
struct SampleStream {
  std::uint64_t state = 0x5EED0D1A5ull;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::int64_t below(std::int64_t n) { return static_cast<std::int64_t>(next() % static_cast<std::uint64_t>(n)); }
};

/// Value of the file's vertex number `n` (i fastest in the given dims).
template <class View>
double at(const View& v, const std::int64_t d[3], std::int64_t n) {
  return v.load(n % d[0], n / d[0] % d[1], n / (d[0] * d[1]));
}

/// Mean |f(a) - f(b)| over finite pairs, from `pairs(stream) -> {a, b}` file vertex numbers.
template <class View, class Pairs>
double mean_difference(const View& v, const std::int64_t d[3], Pairs pairs) {
  SampleStream rng;
  double sum = 0.0;
  int count = 0;
  for (int s = 0; s < kAxisOrderSamples; ++s) {
    const auto [a, b] = pairs(rng);
    const double fa = at(v, d, a), fb = at(v, d, b);
    if (!std::isfinite(fa) || !std::isfinite(fb)) continue;
    sum += std::abs(fa - fb);
    ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

/// Roughness per axis of the file read with dims `c` (a permutation of the given `d`).
template <class View>
std::array<double, 3> roughness(const View& v, const std::int64_t d[3], const std::array<std::int64_t, 3>& c,
                                double random_pair) {
  std::array<double, 3> r{0.0, 0.0, 0.0};
  const std::int64_t step[3] = {1, c[0], c[0] * c[1]};
  for (int axis = 0; axis < 3; ++axis) {
    if (c[axis] < 2) continue;
    const double m = mean_difference(v, d, [&](SampleStream& rng) {
      std::int64_t q[3] = {rng.below(c[0]), rng.below(c[1]), rng.below(c[2])};
      q[axis] = rng.below(c[axis] - 1);
      const std::int64_t n = q[0] + c[0] * (q[1] + c[1] * q[2]);
      return std::pair<std::int64_t, std::int64_t>{n, n + step[axis]};
    });
    r[axis] = m / random_pair;
  }
  return r;
}

/// The roughest axis: one axis read across rows is enough to make stripes.
double worst(const std::array<double, 3>& r) { return std::max({r[0], r[1], r[2]}); }

}  // namespace

std::optional<AxisOrderSuspicion> suspect_axis_order(const FieldView& view) {
  const std::int64_t* d = view.dims;
  if (d[0] < 2 || d[1] < 2 || d[0] * d[1] * d[2] < 8) return std::nullopt;
  return dispatch_dtype(view, [&](auto v) -> std::optional<AxisOrderSuspicion> {
    const std::int64_t total = d[0] * d[1] * d[2];
    const double random_pair = mean_difference(v, d, [&](SampleStream& rng) {
      return std::pair<std::int64_t, std::int64_t>{rng.below(total), rng.below(total)};
    });
    if (!(random_pair > 0.0) || !std::isfinite(random_pair)) return std::nullopt;  // constant, all NaN

    const std::array<std::int64_t, 3> given{d[0], d[1], d[2]};
    const std::array<double, 3> given_r = roughness(v, d, given, random_pair);
    std::array<std::int64_t, 3> c = given;
    std::sort(c.begin(), c.end());
    std::optional<AxisOrderSuspicion> best;
    double best_worst = worst(given_r);
    do {
      if (c == given) continue;
      const std::array<double, 3> r = roughness(v, d, c, random_pair);
      if (worst(r) < best_worst) {
        best_worst = worst(r);
        best = AxisOrderSuspicion{given, c, given_r, r};
      }
    } while (std::next_permutation(c.begin(), c.end()));
    if (!best || !(best_worst * 3.0 <= worst(given_r)) || !(worst(given_r) - best_worst >= 0.3)) return std::nullopt;
    return best;
  });
}

std::string axis_order_warning(const AxisOrderSuspicion& s, const std::string& key) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s [%lld, %lld, %lld] may be in the wrong order: read so, neighbouring vertices along x, y, z "
                "differ by %.2f, %.2f, %.2f of the difference between random vertices (the image will show "
                "stripes), while dims [%lld, %lld, %lld] make the data smooth (%.2f, %.2f, %.2f); %s lists x, "
                "the axis that varies fastest in the file, first",
                key.c_str(), (long long)s.given[0], (long long)s.given[1], (long long)s.given[2], s.given_roughness[0],
                s.given_roughness[1], s.given_roughness[2], (long long)s.better[0], (long long)s.better[1],
                (long long)s.better[2], s.better_roughness[0], s.better_roughness[1], s.better_roughness[2],
                key.c_str());
  return buf;
}

}  // namespace tessera
