#pragma once
/// Owen scrambling by hashing (Laine and Karras 2011; Burley, "Practical Hash-based Owen
/// Scrambling", JCGT 2020; the stronger hash of Vegdahl 2021): a nested uniform scramble of a
/// 32-bit base-2 fraction in which each digit is flipped by a random function of the digits
/// above it only. A scrambled (0,m,2)-net stays a (0,m,2)-net, and every point of it is
/// uniform on [0, 1). Applied to a sample index it is a shuffle that maps each aligned block of
/// 2^k indices onto another aligned block of 2^k indices. Pure functions, no state.
#include <tessera/host_device.h>

#include <cstdint>

namespace tessera {

/// Bit i of x moved to bit 31 - i.
TESSERA_HOST_DEVICE inline std::uint32_t reverse_bits32(std::uint32_t x) {
#if defined(__CUDA_ARCH__)
  return __brev(x);  // the device's bit reversal: the same function
#else
  x = __builtin_bswap32(x);  // the bytes reversed; then the bits within each byte
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
#endif
}

/// A bijection of 32-bit words in which output bit b depends only on input bits 0..b (adds,
/// odd multiplications and x ^= x * even never carry information downwards), keyed by `seed`.
TESSERA_HOST_DEVICE inline std::uint32_t laine_karras_permutation(std::uint32_t x, std::uint32_t seed) {
  x ^= x * 0x3D20ADEAu;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526C56u;
  x ^= x * 0x53A22864u;
  return x;
}

/// Nested uniform scramble of x read as the fraction x / 2^32 (bit 31 the first digit): digit
/// b is flipped by a function of `seed` and the digits before it. A bijection of 32-bit words.
TESSERA_HOST_DEVICE inline std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
  return reverse_bits32(laine_karras_permutation(reverse_bits32(x), seed));
}

}  // namespace tessera
