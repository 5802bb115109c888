#include "heat_sources.h"

#include <cmath>
#include <numbers>

namespace heat {

std::array<double, 3> source_centre(const HeatSource& s, double t) {
  const double angle = 2.0 * std::numbers::pi * t / s.period + s.phase;
  return {s.centre[0] + s.radius * std::cos(angle), s.centre[1] + s.radius * std::sin(angle), s.centre[2]};
}

double source_amplitude(const HeatSource& s, double t) {
  return s.amplitude * (1.0 + s.pulse * std::sin(2.0 * std::numbers::pi * t / s.pulse_period));
}

std::vector<HeatSource> demo_sources() {
  std::vector<HeatSource> s(3);
  s[0] = {{0.5, 0.5, 0.62}, 0.22, 1.0, 0.0, 700.0, 0.3, 0.25, 0.05};
  s[1] = {{0.5, 0.5, 0.38}, 0.22, -1.0, std::numbers::pi, 700.0, 0.3, 0.35, 0.05};
  s[2] = {{0.5, 0.5, 0.2}, 0.0, 1.0, 0.0, 500.0, 0.8, 0.5, 0.07};
  return s;
}

}  // namespace heat
