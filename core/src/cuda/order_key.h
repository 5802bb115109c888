#pragma once
/// Order-preserving integer keys of doubles, so that a device folds min / max with integer
/// atomics: the keys' unsigned order is the doubles' order (no NaN passed). CUDA code only.
#include <cstdint>
#include <cstring>

namespace tessera::cuda {

__host__ __device__ inline unsigned long long order_key(double v) {
  unsigned long long b;
  std::memcpy(&b, &v, sizeof b);
  return (b >> 63) ? ~b : (b | (1ull << 63));
}
__host__ __device__ inline double from_key(unsigned long long k) {
  const unsigned long long b = (k >> 63) ? (k & ~(1ull << 63)) : ~k;
  double v;
  std::memcpy(&v, &b, sizeof v);
  return v;
}

}  // namespace tessera::cuda
