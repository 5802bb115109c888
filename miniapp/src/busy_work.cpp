#include "busy_work.h"

#include <chrono>
#include <cmath>

namespace heat {

double busy_work(double ms) {
  using Clock = std::chrono::steady_clock;
  if (!(ms > 0.0)) return 0.0;
  const auto end =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms));
  // A logistic map, checked against the clock every few thousand iterations
  volatile double sink = 0.0;
  double x = 0.3;
  while (Clock::now() < end) {
    for (int i = 0; i < 4096; ++i) x = 3.9 * x * (1.0 - x);
    sink = sink + x;
  }
  return sink;
}

}  // namespace heat
