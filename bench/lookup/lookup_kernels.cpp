#include "lookup_kernels.h"

#include <algorithm>
#include <cmath>

namespace lookup_bench {

Volume synthetic_volume(int n) {
  Volume v;
  v.nx = v.ny = v.nz = n;
  v.data.resize(std::size_t(n) * n * n);
  std::uint32_t rng = 12345u;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) / n - 0.5, y = (j + 0.5) / n - 0.5, z = (k + 0.5) / n - 0.5;
        const double r = std::sqrt(x * x + y * y + 1.4 * z * z);
        double val = r < 0.42 ? 1000.0 + 80.0 * std::sin(40.0 * x) * std::cos(30.0 * y) : 0.0;  // tissue
        if (r > 0.36 && r < 0.40) val = 1700.0;                                                 // a shell of "bone"
        const double rb = std::sqrt((x - 0.1) * (x - 0.1) + (y + 0.12) * (y + 0.12) + z * z);
        if (rb < 0.08) val = 1900.0;                      // a dense inclusion
        val += 20.0 * (unit_open0(next_u32(rng)) - 0.5);  // noise
        v.data[(std::size_t(k) * n + j) * n + i] = float(std::max(0.0, val));
      }
  return v;
}

Setup make_setup(const Volume& v, int rays, float ramp_lo, float ramp_hi) {
  Setup s;
  const auto [mn, mx] = std::minmax_element(v.data.begin(), v.data.end());
  s.tf_lo = *mn;
  s.tf_hi = *mx > *mn ? *mx : *mn + 1.0f;
  s.sigma.resize(kTableSize + 1);
  for (int i = 0; i <= kTableSize; ++i) {
    const float u = float(i) / kTableSize;  // opacity: a faint haze, then a steep ramp ("bone")
    s.sigma[i] =
        u < ramp_lo ? 0.002f * u : (u < ramp_hi ? 0.002f * ramp_lo + (u - ramp_lo) / (ramp_hi - ramp_lo) * 0.5f : 0.5f);
  }
  s.majorant = *std::max_element(s.sigma.begin(), s.sigma.end());
  const int side = std::max(1, int(std::sqrt(double(rays))));
  const float n[3] = {float(v.nx - 1), float(v.ny - 1), float(v.nz - 1)};
  const float c[3] = {0.5f * n[0], 0.5f * n[1], 0.5f * n[2]};
  const float diag = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const float eye[3] = {c[0] + 1.6f * diag * 0.6f, c[1] + 1.6f * diag * 0.48f, c[2] + 1.6f * diag * 0.64f};
  for (int r = 0; r < rays; ++r) {
    const int px = r % side, py = (r / side) % side;
    // Direction: towards a point of the plane through the centre, spanning the box
    const float sx = (px + 0.5f) / side - 0.5f, sy = (py + 0.5f) / side - 0.5f;
    const float target[3] = {c[0] + sx * diag * 0.8f, c[1] - sx * diag * 0.6f, c[2] + sy * diag};
    Ray ray{};
    float len = 0;
    for (int a = 0; a < 3; ++a) {
      ray.o[a] = eye[a];
      ray.d[a] = target[a] - eye[a];
      len += ray.d[a] * ray.d[a];
    }
    len = std::sqrt(len);
    float t0 = 0.0f, t1 = 1e30f;
    for (int a = 0; a < 3; ++a) {
      ray.d[a] /= len;
      if (ray.d[a] == 0.0f) continue;
      float ta = (0.0f - ray.o[a]) / ray.d[a], tb = (n[a] - ray.o[a]) / ray.d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    ray.t0 = t0;
    ray.t1 = std::max(t0, t1);  // a miss: an empty interval
    s.rays.push_back(ray);
  }
  return s;
}

const char* variant_name(Variant v) {
  switch (v) {
    case Variant::ScalarDouble: return "scalar-double";
    case Variant::ScalarFloat: return "scalar-float";
    case Variant::Interleaved4Double: return "interleaved4-double";
    case Variant::Simd8Float:
    default: return "simd8-float";
  }
}

namespace {

/// The constants of one run in arithmetic type T.
template <class T>
struct Lookup {
  T hi[3];
  std::int64_t sy, sz;
  T inv_maj, scale, lo, maj;
  const float* f;
  const float* sigma;
  Lookup(const Volume& vol, const Setup& s)
      : hi{T(vol.nx - 1), T(vol.ny - 1), T(vol.nz - 1)},
        sy(vol.nx),
        sz(std::int64_t(vol.nx) * vol.ny),
        inv_maj(T(1) / T(s.majorant)),
        scale(T(kTableSize) / (T(s.tf_hi) - T(s.tf_lo))),
        lo(T(s.tf_lo)),
        maj(T(s.majorant)),
        f(vol.data.data()),
        sigma(s.sigma.data()) {}

  /// sigma at distance t along the ray: the trilinear value, then the opacity table.
  [[gnu::always_inline]] T operator()(const Ray& ray, T t) const {
    std::int64_t i[3];
    T w[3];
    for (int a = 0; a < 3; ++a) {
      const T p = std::clamp(T(ray.o[a]) + t * T(ray.d[a]), T(0), hi[a]);
      std::int64_t ii = std::int64_t(p);
      if (ii > std::int64_t(hi[a]) - 1) ii = std::int64_t(hi[a]) - 1;
      i[a] = ii;
      w[a] = p - T(ii);
    }
    const float* c = f + i[0] + i[1] * sy + i[2] * sz;
    const T c00 = T(c[0]) + w[0] * (T(c[1]) - T(c[0])), c10 = T(c[sy]) + w[0] * (T(c[sy + 1]) - T(c[sy]));
    const T c01 = T(c[sz]) + w[0] * (T(c[sz + 1]) - T(c[sz]));
    const T c11 = T(c[sy + sz]) + w[0] * (T(c[sy + sz + 1]) - T(c[sy + sz]));
    const T c0 = c00 + w[1] * (c10 - c00), c1 = c01 + w[1] * (c11 - c01);
    const T value = c0 + w[2] * (c1 - c0);
    T x = std::clamp((value - lo) * scale, T(0), T(kTableSize));
    int b = int(x);
    if (b > kTableSize - 1) b = kTableSize - 1;
    return T(sigma[b]) + (x - T(b)) * (T(sigma[b + 1]) - T(sigma[b]));
  }
};

/// One ray at a time in arithmetic type T: the kernel's loop reduced to its lookups.
template <class T>
Result run_scalar(const Volume& vol, const Setup& s) {
  Result res;
  const Lookup<T> lookup(vol, s);
  for (std::size_t r = 0; r < s.rays.size(); ++r) {
    const Ray& ray = s.rays[r];
    std::uint32_t rng = ray_seed(std::uint32_t(r));
    T t = ray.t0;
    for (;;) {
      t -= std::log(T(unit_open0(next_u32(rng)))) * lookup.inv_maj;
      if (!(t < T(ray.t1))) break;
      const T sigma = lookup(ray, t);
      ++res.lookups;
      res.checksum += double(sigma);
      if (T(unit_open0(next_u32(rng))) * lookup.maj < sigma) break;  // a real collision
    }
  }
  return res;
}

/// Four rays at once in scalar double, round robin: each pass advances every lane by one
/// step (one tentative collision), and a lane whose ray ends takes the next ray. The same
/// arithmetic per ray as run_scalar<double>; the rays' steps are interleaved so that one
/// ray's dependent chain (position, samples, blend, table, compare) can overlap another's.
/// It asks whether a scalar wavefront alone buys anything without SIMD lanes.
Result run_interleaved4(const Volume& vol, const Setup& s) {
  constexpr int kLanes = 4;
  Result res;
  const Lookup<double> lookup(vol, s);
  struct Lane {
    const Ray* ray = nullptr;
    std::uint32_t rng = 0;
    double t = 0;
  } lane[kLanes];
  std::size_t next = 0;
  const auto take = [&](Lane& l) {
    if (next < s.rays.size()) {
      l.ray = &s.rays[next];
      l.rng = ray_seed(std::uint32_t(next));
      l.t = l.ray->t0;
      ++next;
    } else {
      l.ray = nullptr;
    }
  };
  for (Lane& l : lane) take(l);
  for (int active = kLanes; active > 0;) {
    active = 0;
    for (Lane& l : lane) {
      if (!l.ray) continue;
      ++active;
      l.t -= std::log(double(unit_open0(next_u32(l.rng)))) * lookup.inv_maj;
      if (!(l.t < double(l.ray->t1))) {
        take(l);
        continue;
      }
      const double sigma = lookup(*l.ray, l.t);
      ++res.lookups;
      res.checksum += sigma;
      if (double(unit_open0(next_u32(l.rng))) * lookup.maj < sigma) take(l);  // a real collision
    }
  }
  return res;
}

bool cpu_has_avx2() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

}  // namespace

bool simd_gathers() {
#ifdef TESSERA_LOOKUP_AVX2
  return cpu_has_avx2();
#else
  return false;
#endif
}

Result run(Variant v, const Volume& vol, const Setup& s) {
  switch (v) {
    case Variant::ScalarDouble: return run_scalar<double>(vol, s);
    case Variant::ScalarFloat: return run_scalar<float>(vol, s);
    case Variant::Interleaved4Double: return run_interleaved4(vol, s);
    case Variant::Simd8Float:
    default:
#ifdef TESSERA_LOOKUP_AVX2
      if (simd_gathers()) return run_simd8_avx2(vol, s);
#endif
      return run_simd8_generic(vol, s);
  }
}

}  // namespace lookup_bench
