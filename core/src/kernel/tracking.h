#pragma once
/// The one tracking loop: a walk over the macrocells a ray crosses and, in each, exponential
/// steps against the cell's majorant, handing every tentative collision to a callback (the
/// idea of pbrt-v4's SampleT_maj). Free-flight sampling (delta tracking) and both
/// transmittance estimators (ratio and delta tracking) are callbacks of this loop; the
/// estimator is a template parameter (TransmittanceStep), resolved once per frame.
/// The biased fixed-step march (FreePath::Raymarch) is the other free-flight strategy.
/// Allocates nothing, throws nothing.
#include <tessera/integrator.h>
#include <tessera/loop_bounds.h>

#include "kernel/grid_medium.h"
#include "sampling/exponential.h"
#include "sampling/rng.h"

#include <algorithm>
#include <cmath>

namespace tessera {

/// How a majorant walk ended.
enum class TrackEnd {
  Done,     ///< reached t1: the callback never asked to stop
  Stopped,  ///< the callback returned false
  Stalled,  ///< a loop guard: a step that did not advance t, or over kMaxTrackingSteps steps
};

/// Samples tentative collisions along the voxel-space ray p(t) = ov + t dv over world
/// distances [t0, t1]: one Exp(1) optical depth tau at a time, spent over the macrocells'
/// majorants (a cell with majorant maj > 0 over a length l spends maj l of it; empty cells
/// spend none and are crossed in closed form), and a tentative collision where tau runs out,
/// calling fn(p, t, maj) there; fn returns false to stop the walk. By the exponential's
/// memorylessness this is delta tracking's step distribution exactly, with one logarithm per
/// tentative collision instead of one per non-empty cell crossed. One rng draw per
/// collision before fn (fn draws what it needs itself); none for a ray that meets only empty cells.
template <class V, class Fn>
TESSERA_HOST_DEVICE TrackEnd sample_majorant_steps(const GridMedium<V>& m, const Vec3& ov, const Vec3& dv, double t0,
                                                   double t1, Rng& rng, Fn&& fn) {
  double budget = kMaxTrackingSteps;
  bool stalled = false;
  double tau = -1.0;  // optical depth left to the next tentative collision (drawn at the first non-empty cell)
  const bool stopped = traverse_macrocells(
      m, ov, dv, t0, t1, [&](double ta, double tb, double maj) __attribute__((always_inline)) {
        if (maj <= 0.0) return false;
        if (tau < 0.0) tau = exp_unit(rng);
        for (double t = ta;;) {
          const double dt = tau / maj;
          const double t_next = t + dt;
          if (t_next >= tb) {
            tau = std::max(0.0, tau - (tb - t) * maj);  // the rest carries into the next cell
            return false;
          }
          if ((!(t_next > t) && dt > 0.0) || --budget < 0.0) {
            stalled = true;
            return true;
          }
          t = t_next;
          if (!fn(ov + t * dv, t, maj)) return true;
          tau = exp_unit(rng);
        }
      });
  return stalled ? TrackEnd::Stalled : (stopped ? TrackEnd::Stopped : TrackEnd::Done);
}

/// One tentative collision's update of a transmittance estimate T, per shadow estimator.
/// Ratio tracking multiplies by the null-collision probability; with `roulette`, an estimate
/// below kShadowRouletteT survives with probability T / kShadowRouletteT and is then set to
/// kShadowRouletteT (its expectation stays T), else ends at 0. Delta tracking ends at 0 on
/// a real collision.
inline constexpr double kShadowRouletteT = 0.25;
template <ShadowMode kMode>
struct TransmittanceStep;

template <>
struct TransmittanceStep<ShadowMode::Ratio> {
  TESSERA_HOST_DEVICE static void apply(double& T, double sigma, double maj, bool roulette, Rng& rng) {
    T *= 1.0 - sigma / maj;
    if (roulette && T < kShadowRouletteT && T > 0.0) T = rng.uniform() * kShadowRouletteT < T ? kShadowRouletteT : 0.0;
  }
};

template <>
struct TransmittanceStep<ShadowMode::Delta> {
  TESSERA_HOST_DEVICE static void apply(double& T, double sigma, double maj, bool, Rng& rng) {
    if (rng.uniform() * maj < sigma) T = 0.0;
  }
};

/// Fixed-step march (biased): steps of h from t0 + U h, accumulating sigma h until it passes
/// an Exp(1) threshold. Visits `on_lookup` once per field sample. Returns 1 on a collision
/// (*t_hit set), 0 when the ray leaves [t0, t1), -1 when over kMaxMarchSteps steps.
template <class V, class Lookup>
TESSERA_HOST_DEVICE int march_free_flight(const GridMedium<V>& m, const Vec3& ov, const Vec3& dv, double t0, double t1,
                                          double h, Rng& rng, double* t_hit, Lookup&& on_lookup) {
  const double tau = exp_unit(rng);
  double sum = 0.0;
  double budget = kMaxMarchSteps + 2.0;
  for (double t = t0 + rng.uniform() * h; t < t1; t += h) {
    if (--budget < 0.0) return -1;
    on_lookup();
    sum += m.sigma_t(ov + t * dv) * h;
    if (sum >= tau) {
      *t_hit = t;
      return 1;
    }
  }
  return 0;
}

}  // namespace tessera
