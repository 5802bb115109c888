#pragma once
/// Per-sample random streams: xorshift64* (Vigna 2016, as in the thesis), seeded from a
/// splitmix64 hash of (seed, frame, pixel, sample). A stream is a pure function of those four
/// numbers, so no thread, tile or rank can change what a sample draws.
#include <tessera/host_device.h>

#include <cstdint>

namespace tessera {

TESSERA_HOST_DEVICE inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

class Rng {
 public:
  TESSERA_HOST_DEVICE Rng(std::uint64_t seed, std::uint64_t frame, std::uint64_t pixel, std::uint64_t sample) {
    std::uint64_t h = splitmix64(seed);
    h = splitmix64(h ^ frame);
    h = splitmix64(h ^ pixel);
    h = splitmix64(h ^ sample);
    m_state = h ? h : 0x2545F4914F6CDD1Dull;
  }
  TESSERA_HOST_DEVICE std::uint64_t next_u64() {
    m_state ^= m_state >> 12;
    m_state ^= m_state << 25;
    m_state ^= m_state >> 27;
    return m_state * 0x2545F4914F6CDD1Dull;
  }
  /// Uniform double in [0, 1) with 53 random bits.
  TESSERA_HOST_DEVICE double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t m_state;
};

}  // namespace tessera
