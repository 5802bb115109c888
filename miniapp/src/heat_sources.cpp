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

double steady_excess(const HeatSource& s, double t, double alpha, const std::array<double, 3>& x) {
  const std::array<double, 3> c = source_centre(s, t);
  const double dx = x[0] - c[0], dy = x[1] - c[1], dz = x[2] - c[2];
  const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
  const double peak = source_amplitude(s, t) * s.sigma * s.sigma / alpha;
  // erf(z) / z -> 2 / sqrt(pi) as z -> 0: below 1e-6 sigma the centre value is exact to 1e-12
  const double z = r / (std::numbers::sqrt2 * s.sigma);
  if (z < 1e-6) return peak;
  return peak * std::sqrt(std::numbers::pi) / 2.0 * std::erf(z) / z;
}

std::vector<HeatSource> demo_sources() {
  std::vector<HeatSource> s(3);
  s[0] = {{0.5, 0.5, 0.62}, 0.22, 1.0, 0.0, 700.0, 0.3, 0.25, 0.05};
  s[1] = {{0.5, 0.5, 0.38}, 0.22, -1.0, std::numbers::pi, 700.0, 0.3, 0.35, 0.05};
  s[2] = {{0.5, 0.5, 0.2}, 0.0, 1.0, 0.0, 500.0, 0.8, 0.5, 0.07};
  return s;
}

}  // namespace heat
