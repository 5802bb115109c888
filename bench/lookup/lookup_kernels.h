#pragma once
/// The bare lookup loop of bench/lookup/lookup_limit.cpp: a trilinear lookup of a float32
/// volume plus a transfer-function opacity lookup at exponential steps along rays (delta
/// tracking against a constant majorant, stopping at a real collision), in four variants.
/// Every variant draws the same random numbers per ray, so their checksums agree up to the
/// precision of their arithmetic.
#include <cstdint>
#include <string>
#include <vector>

namespace lookup_bench {

struct Volume {
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> data;  ///< x fastest
  std::string name;
};

/// A CT-like test volume: smooth tissue, sharp-edged "bone" shells, noise; values in [0, 2000].
Volume synthetic_volume(int n);

struct Ray {
  float o[3], d[3];  ///< voxel space, |d| = 1 (t in voxels)
  float t0, t1;      ///< the part inside the box [0, n-1]
};

struct Setup {
  std::vector<Ray> rays;       ///< coherent: a pinhole camera's pixels, row by row
  std::vector<float> sigma;    ///< opacity table over [tf_lo, tf_hi], kTableSize + 1 entries, per voxel
  float tf_lo = 0, tf_hi = 1;  ///< the volume's value range
  float majorant = 0;          ///< max of the table: a global majorant per voxel
};
inline constexpr int kTableSize = 256;

/// Rays through the volume's box from a camera at 1.6 box diagonals, and a CT-like opacity
/// transfer function over the volume's value range: a faint haze, then a sharp ramp between
/// the fractions ramp_lo < ramp_hi of the range (the "bone"), opaque above.
Setup make_setup(const Volume& v, int rays, float ramp_lo, float ramp_hi);

enum class Variant { ScalarDouble, ScalarFloat, Interleaved4Double, Simd8Float };
const char* variant_name(Variant v);

struct Result {
  std::uint64_t lookups = 0;
  double checksum = 0;  ///< sum of sigma over every lookup
};
Result run(Variant v, const Volume& vol, const Setup& s);

/// True when the 8-wide variant uses AVX2 gathers (the CPU has AVX2 and FMA).
bool simd_gathers();

// The 8-wide loop, in two builds of lookup_simd.inc: with AVX2 gathers, and portable.
Result run_simd8_avx2(const Volume& vol, const Setup& s);
Result run_simd8_generic(const Volume& vol, const Setup& s);

/// Per-ray random numbers shared by the variants: xorshift32 seeded by the ray's index.
inline std::uint32_t ray_seed(std::uint32_t ray) {
  std::uint32_t h = ray * 0x9E3779B9u + 0x7F4A7C15u;
  h ^= h >> 16;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  return h | 1u;
}
inline std::uint32_t next_u32(std::uint32_t& s) {
  s ^= s << 13;
  s ^= s >> 17;
  s ^= s << 5;
  return s;
}
/// In (0, 1]: never 0, so its logarithm is finite.
inline float unit_open0(std::uint32_t r) { return float((r >> 8) + 1) * (1.0f / 16777216.0f); }

}  // namespace lookup_bench
