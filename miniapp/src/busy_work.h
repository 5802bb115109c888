#pragma once
/// tessera-heat --work-ms: real computation added to each step, so that the miniapp can stand
/// for a simulation whose steps take longer than its small explicit solver's (docs/miniapp.md).
namespace heat {

/// The most --work-ms accepts: one minute per step.
inline constexpr long long kMaxWorkMs = 60000;

/// Computes (floating-point arithmetic the compiler cannot drop, no sleeping) until `ms`
/// milliseconds of wall time have passed; returns a value that depends on the work done.
/// ms <= 0: returns at once.
double busy_work(double ms);

}  // namespace heat
