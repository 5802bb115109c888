#pragma once
/// Two independent 64-bit hashes of a byte string, for comparing data across ranks without
/// sending it (rank_agreement.h): FNV-1a 64 and MurmurHash64A. Two different functions, so a
/// collision would have to happen in both at once (about 2^-128 for unrelated inputs).
/// Not cryptographic: they guard against accidents, not adversaries.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace tessera::insitu {

/// FNV-1a, 64-bit (offset basis 14695981039346656037, prime 1099511628211).
inline std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = 14695981039346656037ull) {
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

/// MurmurHash64A (Austin Appleby, public domain), little-endian word reads via memcpy.
inline std::uint64_t murmur64a(std::string_view bytes, std::uint64_t seed = 0x9e3779b97f4a7c15ull) {
  constexpr std::uint64_t m = 0xc6a4a7935bd1e995ull;
  constexpr int r = 47;
  const std::size_t len = bytes.size();
  std::uint64_t h = seed ^ (len * m);
  const char* p = bytes.data();
  for (std::size_t i = 0; i + 8 <= len; i += 8, p += 8) {
    std::uint64_t k;
    std::memcpy(&k, p, 8);
    k *= m;
    k ^= k >> r;
    k *= m;
    h ^= k;
    h *= m;
  }
  const std::size_t tail = len & 7;
  if (tail) {
    std::uint64_t k = 0;
    for (std::size_t i = 0; i < tail; ++i) k |= static_cast<std::uint64_t>(static_cast<unsigned char>(p[i])) << (8 * i);
    h ^= k;
    h *= m;
  }
  h ^= h >> r;
  h *= m;
  h ^= h >> r;
  return h;
}

}  // namespace tessera::insitu
