#pragma once
/// Exp(1) variates for the tracking loop's steps: the ziggurat method (Marsaglia and Tsang
/// 2000) over the layer tables of exponential_tables.h. About 98.9% of draws take one 64-bit
/// random number, an integer compare and a multiply; the rest take the wedge's exp() or the
/// tail's log() and may draw again. Exact in distribution up to the 53-bit resolution of a
/// layer (the tables are computed in 60-digit arithmetic, scripts/gen_exponential_tables.py).
#include "sampling/exponential_tables.h"
#include "sampling/rng.h"

#include <cmath>
#include <cstdint>

namespace tessera {

namespace detail {

TESSERA_DEVICE_TABLE(kExpZigguratK);
TESSERA_DEVICE_TABLE(kExpZigguratW);
TESSERA_DEVICE_TABLE(kExpZigguratF);

/// One 64-bit draw read as a ziggurat layer (its low 8 bits) and a position x in the layer's
/// rectangle (its high 53 bits times the layer's width); true when x lies in the layer's
/// core, under the curve whatever the height: x is then an Exp(1) variate.
[[gnu::always_inline]] TESSERA_HOST_DEVICE inline bool exp_ziggurat_core(std::uint64_t bits, unsigned* layer,
                                                                         double* x) {
  *layer = static_cast<unsigned>(bits & 0xFF);
  const std::uint64_t m = bits >> 11;
  *x = static_cast<double>(m) * TESSERA_TABLE(kExpZigguratW)[*layer];
  return m < TESSERA_TABLE(kExpZigguratK)[*layer];
}

/// The draws outside a layer's core: the tail beyond r (layer 0, memoryless: r + Exp(1) by
/// inversion) or a wedge test (layer i >= 1), drawing again on rejection.
[[gnu::noinline]] TESSERA_HOST_DEVICE inline double exp_ziggurat_slow(Rng& rng, unsigned layer, double x) {
  for (;;) {
    if (layer == 0) return kExpZigguratR - std::log(1.0 - rng.uniform());
    const double f_lo = TESSERA_TABLE(kExpZigguratF)[layer], f_hi = TESSERA_TABLE(kExpZigguratF)[layer + 1];
    if (f_lo + rng.uniform() * (f_hi - f_lo) < std::exp(-x)) return x;
    if (exp_ziggurat_core(rng.next_u64(), &layer, &x)) return x;
  }
}

}  // namespace detail

/// One Exp(1) variate (unit-rate exponential) from rng's stream: the layer from the low 8
/// bits of one draw, the position within it from the high 53.
[[gnu::always_inline]] TESSERA_HOST_DEVICE inline double exp_unit(Rng& rng) {
  unsigned layer;
  double x;
  if (detail::exp_ziggurat_core(rng.next_u64(), &layer, &x)) [[likely]]
    return x;
  return detail::exp_ziggurat_slow(rng, layer, x);
}

}  // namespace tessera
