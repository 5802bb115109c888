#pragma once
/// Heat sources: Gaussian blobs that circle and pulse, so that the temperature field (and the
/// images of it) change from step to step.
///
/// Source s adds heat at the rate
///   q_s(x, t) = A_s (1 + p_s sin(2 pi t / P_s)) exp(-|x - c_s(t)|^2 / (2 sigma_s^2))   [K / s]
/// around a centre moving on a horizontal circle:
///   c_s(t) = centre_s + radius_s (cos(2 pi t / T_s + phase_s), sin(2 pi t / T_s + phase_s), 0).
/// Positions are in the unit-cube domain coordinates.
#include <array>
#include <vector>

namespace heat {

struct HeatSource {
  std::array<double, 3> centre{0.5, 0.5, 0.5};  ///< centre of the orbit
  double radius = 0.0;                          ///< orbit radius (0: fixed)
  double period = 1.0;                          ///< orbit period T_s, s (!= 0; negative: clockwise)
  double phase = 0.0;                           ///< orbit phase, radians
  double amplitude = 0.0;                       ///< A_s, K / s
  double pulse = 0.0;                           ///< p_s in [0, 1]: relative pulsation of the amplitude
  double pulse_period = 1.0;                    ///< P_s, s (> 0)
  double sigma = 0.05;                          ///< width, domain units (> 0)
};

/// Where a source is at time t, and its amplitude then.
std::array<double, 3> source_centre(const HeatSource& s, double t);
double source_amplitude(const HeatSource& s, double t);

/// The source's steady free-space temperature excess at x (K): the solution of
///   alpha laplacian(u) = -q_s(x)   with u -> 0 far away,
/// for the source frozen at time t (its centre and amplitude then):
///   u(r) = Q / (4 pi alpha r) erf(r / (sqrt(2) sigma)),  Q = A (2 pi)^(3/2) sigma^3,
/// r = |x - c_s(t)|; u(0) = A sigma^2 / alpha. tessera-heat --amr uses it for the detail of the
/// source below the coarse grid's resolution (amr_levels.h).
double steady_excess(const HeatSource& s, double t, double alpha, const std::array<double, 3>& x);

/// The demo's sources: two blobs orbiting the vertical axis in opposite directions at
/// different heights, and a slowly pulsing one near the floor.
std::vector<HeatSource> demo_sources();

}  // namespace heat
