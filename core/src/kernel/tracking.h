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

/// What MajorantSteps::next found.
enum class TrackStep {
  Collision,  ///< a tentative collision at t() (position(), majorant())
  Done,       ///< reached t1
  Stalled,    ///< a loop guard: a step that did not advance t, or over kMaxTrackingSteps steps
};

/// The tentative collisions along the voxel-space ray p(t) = ov + t dv over world distances
/// [t0, t1], one per next(): one Exp(1) optical depth tau at a time, spent over the
/// macrocells' majorants (a cell with majorant maj > 0 over a length l spends maj l of it;
/// empty cells spend none and are crossed in closed form), and a tentative collision where
/// tau runs out. By the exponential's memorylessness this is delta tracking's step
/// distribution exactly, with one logarithm per tentative collision instead of one per
/// non-empty cell crossed. Draws from rng: the first tau at the first non-empty cell, and
/// the next tau when next() is called again after a collision (so the caller's own draws at
/// a collision come first); none for a ray that meets only empty cells. Resumable: a caller
/// may keep it and do other work between steps (sample_majorant_steps is the loop).
template <class V>
class MajorantSteps {
 public:
  /// A walk with no collisions (a placeholder to assign a walk to).
  MajorantSteps() = default;
  [[gnu::always_inline]] TESSERA_HOST_DEVICE MajorantSteps(const GridMedium<V>& m, const Vec3& ov, const Vec3& dv,
                                                           double t0, double t1)
      : m_walk(m, ov, dv, t0, t1), m_ov(ov), m_dv(dv) {}

  [[gnu::always_inline]] TESSERA_HOST_DEVICE TrackStep next(Rng& rng) {
    if (m_redraw) {
      m_tau = exp_unit(rng);
      m_redraw = false;
    }
    for (;;) {
      if (!m_in_cell) {
        typename MacrocellWalk<V>::Segment seg;
        if (!m_walk.next(seg)) return TrackStep::Done;
        if (seg.majorant <= 0.0) continue;
        if (m_tau < 0.0) m_tau = exp_unit(rng);
        m_t = seg.ta;
        m_tb = seg.tb;
        m_maj = seg.majorant;
        m_in_cell = true;
      }
      const double dt = m_tau / m_maj;
      const double t_next = m_t + dt;
      if (t_next >= m_tb) {
        m_tau = std::max(0.0, m_tau - (m_tb - m_t) * m_maj);  // the rest carries into the next cell
        m_in_cell = false;
        continue;
      }
      if ((!(t_next > m_t) && dt > 0.0) || --m_budget < 0.0) return TrackStep::Stalled;
      m_t = t_next;
      m_redraw = true;
      return TrackStep::Collision;
    }
  }

  TESSERA_HOST_DEVICE double t() const { return m_t; }
  TESSERA_HOST_DEVICE double majorant() const { return m_maj; }
  TESSERA_HOST_DEVICE Vec3 position() const { return m_ov + m_t * m_dv; }

 private:
  MacrocellWalk<V> m_walk;
  Vec3 m_ov{0.0}, m_dv{0.0};
  double m_tau = -1.0;  ///< optical depth left to the next tentative collision (drawn at the first non-empty cell)
  double m_budget = kMaxTrackingSteps;
  double m_t = 0.0, m_tb = 0.0, m_maj = 0.0;  ///< within the current cell: position, exit, majorant
  bool m_in_cell = false;
  bool m_redraw = false;  ///< a collision was handed out: draw the next tau first
};

/// How a majorant walk ended.
enum class TrackEnd {
  Done,     ///< reached t1: the callback never asked to stop
  Stopped,  ///< the callback returned false
  Stalled,  ///< a loop guard: a step that did not advance t, or over kMaxTrackingSteps steps
};

/// MajorantSteps' collisions handed to fn(p, t, maj) in order, until fn returns false.
template <class V, class Fn>
TESSERA_HOST_DEVICE TrackEnd sample_majorant_steps(const GridMedium<V>& m, const Vec3& ov, const Vec3& dv, double t0,
                                                   double t1, Rng& rng, Fn&& fn) {
  MajorantSteps<V> steps(m, ov, dv, t0, t1);
  for (;;) {
    const TrackStep r = steps.next(rng);
    if (r == TrackStep::Done) return TrackEnd::Done;
    if (r == TrackStep::Stalled) return TrackEnd::Stalled;
    if (!fn(steps.position(), steps.t(), steps.majorant())) return TrackEnd::Stopped;
  }
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
