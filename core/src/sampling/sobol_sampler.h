#pragma once
/// SobolSampler: low-discrepancy sample values for the first dimensions of a path, a padded,
/// Owen-scrambled (0,2)-sequence (the first two dimensions of Sobol': van der Corput and its
/// Pascal-matrix partner). Each dimension, or pair of dimensions, of a sample reads point
/// `index` of its own copy of the sequence, the index shuffled and the point Owen-scrambled
/// (owen_scramble.h) by hashes of (seed, frame, pixel, dimension): within a pixel the samples
/// 0..2^k-1 of one pair form a (0,k,2)-net (stratified in every 2^-a x 2^-(k-a) box), while
/// distinct pairs are independent of one another (the padding). Every value is uniform on
/// [0, 1) and a pure function of (seed, frame, pixel, index, dimension), like Rng, so threads,
/// tiles, ranks and adaptive sampling (which continues a pixel's indices) cannot change it.
/// Indices run on 32 bits; the index's upper 32 bits key a fresh scramble, so a pixel's 2^32
/// samples after the first 2^32 are new ones. Values are multiples of 2^-32. No state beyond
/// two words, no allocation; trivially copyable.
#include "sampling/owen_scramble.h"
#include "sampling/rng.h"

#include <array>
#include <cstdint>

namespace tessera {

/// Sobol's second dimension per index byte: entry [k][b] is the xor of the generator matrix's
/// columns for the set bits of b << 8k. The matrix is Pascal's triangle mod 2: column 0 is the
/// fraction 1/2, each next column the previous one xor itself shifted down a digit.
inline constexpr std::array<std::array<std::uint32_t, 256>, 4> kSobol1Bytes = [] {
  std::array<std::uint32_t, 32> col{};
  std::uint32_t v = 0x80000000u;
  for (int b = 0; b < 32; ++b, v ^= v >> 1) col[static_cast<std::size_t>(b)] = v;
  std::array<std::array<std::uint32_t, 256>, 4> t{};
  for (int k = 0; k < 4; ++k)
    for (int byte = 0; byte < 256; ++byte) {
      std::uint32_t x = 0;
      for (int b = 0; b < 8; ++b)
        if (byte >> b & 1) x ^= col[static_cast<std::size_t>(8 * k + b)];
      t[static_cast<std::size_t>(k)][static_cast<std::size_t>(byte)] = x;
    }
  return t;
}();
TESSERA_DEVICE_TABLE(kSobol1Bytes);

/// The dimensions read from the sampler: a 2D pair each for the pixel jitter, the lens, the
/// first collision's light sample (u, v) and its scattering direction; one each for that
/// collision's light pick, its hybrid BRDF/phase choice and its BRDF lobe choice. Every other
/// random number of a path comes from its Rng.
enum class SampleDim : std::uint32_t {
  Pixel = 0,
  Lens = 1,
  LightUv = 2,
  Direction = 3,
  LightPick = 4,
  ScatterChoice = 5,
  Lobe = 6,
};

struct Sample2 {
  double x, y;
};

class SobolSampler {
 public:
  TESSERA_HOST_DEVICE SobolSampler(std::uint64_t seed, std::uint64_t frame, std::uint64_t pixel, std::uint64_t index)
      : m_index_reversed(reverse_bits32(static_cast<std::uint32_t>(index))) {
    std::uint64_t h = splitmix64(seed ^ 0x50B01D1D0C5EED5Full);  // apart from Rng's hash of the same numbers
    h = splitmix64(h ^ frame);
    h = splitmix64(h ^ pixel);
    m_key = splitmix64(h ^ (index >> 32));
  }

  /// Values for a pair of dimensions, each uniform on [0, 1).
  TESSERA_HOST_DEVICE Sample2 get_2d(SampleDim d) const {
    const std::uint64_t h = splitmix64(m_key ^ (static_cast<std::uint64_t>(d) << 1));
    const std::uint32_t i = shuffled_index(static_cast<std::uint32_t>(h));
    const std::uint32_t s = static_cast<std::uint32_t>(h >> 32);
    const std::uint32_t x = scrambled_van_der_corput(i, s);
    const std::uint32_t y = owen_scramble(sobol_dim1(i), static_cast<std::uint32_t>(splitmix64(h)));
    return {to_unit(x), to_unit(y)};
  }

  /// A value for a single dimension, uniform on [0, 1) (a scrambled van der Corput sequence).
  TESSERA_HOST_DEVICE double get_1d(SampleDim d) const {
    const std::uint64_t h = splitmix64(m_key ^ ((static_cast<std::uint64_t>(d) << 1) | 1u));
    const std::uint32_t i = shuffled_index(static_cast<std::uint32_t>(h));
    return to_unit(scrambled_van_der_corput(i, static_cast<std::uint32_t>(h >> 32)));
  }

  /// Point i of Sobol's second dimension, as a 32-bit fraction: the xor of the generator
  /// matrix's columns for the index's set bits, a byte at a time (kSobol1Bytes).
  TESSERA_HOST_DEVICE static std::uint32_t sobol_dim1(std::uint32_t i) {
    const auto& t = TESSERA_TABLE(kSobol1Bytes);
    return t[0][i & 0xFFu] ^ t[1][(i >> 8) & 0xFFu] ^ t[2][(i >> 16) & 0xFFu] ^ t[3][i >> 24];
  }

 private:
  std::uint64_t m_key;             ///< hash of (seed, frame, pixel, index's upper half)
  std::uint32_t m_index_reversed;  ///< the index's lower half, bits reversed (owen_scramble's first step)

  TESSERA_HOST_DEVICE static double to_unit(std::uint32_t x) { return static_cast<double>(x) * 0x1.0p-32; }
  /// The index shuffled by a nested scramble of its bits from the top one down (owen_scramble
  /// read with bit 0 first): each aligned block of 2^k indices lands on one such block.
  TESSERA_HOST_DEVICE std::uint32_t shuffled_index(std::uint32_t seed) const {
    return reverse_bits32(laine_karras_permutation(m_index_reversed, seed));
  }
  /// owen_scramble(reverse_bits32(i), seed), van der Corput's point i scrambled, with the two
  /// reversals in a row left out.
  TESSERA_HOST_DEVICE static std::uint32_t scrambled_van_der_corput(std::uint32_t i, std::uint32_t seed) {
    return reverse_bits32(laine_karras_permutation(i, seed));
  }
};

/// Dimension `d` from `ld` when given, else the next value of `rng`: the one call site serves
/// both samplers, and without `ld` the stream is drawn exactly as before.
TESSERA_HOST_DEVICE inline double sample_1d(const SobolSampler* ld, SampleDim d, Rng& rng) {
  return ld ? ld->get_1d(d) : rng.uniform();
}

/// Pair `d` from `ld` when given, else the next two values of `rng` (x first).
TESSERA_HOST_DEVICE inline Sample2 sample_2d(const SobolSampler* ld, SampleDim d, Rng& rng) {
  if (ld) return ld->get_2d(d);
  const double x = rng.uniform();
  return {x, rng.uniform()};
}

}  // namespace tessera
