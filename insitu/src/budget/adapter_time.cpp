// The process's running sum of time inside adapters (adapter_time.h).
#include "budget/adapter_time.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>

namespace tessera::insitu {
namespace {

/// Nanoseconds: an integer, so concurrent additions are exact and never lost.
std::atomic<std::int64_t>& total_ns() {
  static std::atomic<std::int64_t> t{0};
  return t;
}

}  // namespace

void add_adapter_time(double seconds) noexcept {
  if (!(seconds > 0.0) || !std::isfinite(seconds)) return;
  const double ns = std::min(seconds * 1e9, 9.0e18);  // (a call of 285 years at most)
  total_ns().fetch_add(static_cast<std::int64_t>(ns), std::memory_order_relaxed);
}

double adapter_time_total() noexcept { return static_cast<double>(total_ns().load(std::memory_order_relaxed)) * 1e-9; }

}  // namespace tessera::insitu
