#pragma once
/// BudgetPlanner: how many samples per pixel the renders of one execute call get under
/// `tessera.budget` (docs/insitu.md, "Controlling the cost"). Pure arithmetic: no clock, no
/// MPI, no YAML; the adapter feeds it times (render_budget.h) and carries rank 0's plan to
/// every rank in the call's agreement (rank_agreement.h).
///
/// The account. Each call adds budget x the simulation's seconds since the last call that
/// rendered, and takes away the seconds the call spent inside the adapter. A positive balance
/// (time under budget) is carried forward, at most what one call of the same renders at full
/// `spp` would cost; a negative one (time over budget) is paid back by later calls, which
/// then plan fewer samples or skip.
///
/// The cost model, per render: seconds = overhead + per_spp x spp, learnt from the renders
/// it made (rendering time, all Cinema views, proportional to spp; the rest of the render,
/// preparing, denoising, writing, as overhead), half old and half new estimate each time.
///
/// The plan, one number per call: a share f of every firing render's `spp`, chosen so that
/// the call's renders at f x spp cost at most the balance. A render gets
/// planned_spp(f, spp, min_spp) = floor(f x spp), or is skipped when that is below its
/// min_spp (the time it leaves is carried forward). A call in which a render fires that has
/// not rendered yet (nothing to learn from) plans kLearnPlan, every render at its min_spp,
/// if the account is not in debt; otherwise it skips until the debt is paid.
#include <cstddef>
#include <span>
#include <vector>

namespace tessera::insitu {

/// One render's bounds on the samples per pixel a plan may give it: 1 <= min_spp <= spp.
struct BudgetLimits {
  int spp = 1;
  int min_spp = 1;
};

/// The plan of a call that learns: every firing render at its min_spp.
inline constexpr double kLearnPlan = -1.0;

/// The samples per pixel `plan` gives a render with these limits: in [min_spp, spp], or 0
/// (skipped). plan >= 1 (or anything not below 1: +inf) gives spp; kLearnPlan (any plan < 0)
/// gives min_spp; a plan in [0, 1) gives floor(plan x spp) if that reaches min_spp; NaN
/// skips. The same on every rank for the same bits of `plan`.
int planned_spp(double plan, const BudgetLimits& limits);

class BudgetPlanner {
 public:
  /// budget: the fraction of the simulation's time rendering may take, > 0 (a budget <= 0
  /// or NaN is treated as the smallest positive one). One BudgetLimits per config render.
  BudgetPlanner(double budget, std::vector<BudgetLimits> renders);

  /// A call begins: `simulation_seconds` (negative or NaN counts as 0) since the last call
  /// that rendered; firing[i] != 0 for each render that fires or may fire (size: the
  /// renders; missing entries do not fire; +inf counts as the largest finite time). Adds the call's share to the account and
  /// returns the plan: kLearnPlan, or a share in [0, 1].
  double plan(double simulation_seconds, std::span<const unsigned char> firing);

  /// Render i ran with `spp` samples per pixel (> 0): `render_seconds` tracing samples (all
  /// its views), `other_seconds` the rest of it. Not called for a render that was skipped or
  /// failed. Negative or NaN seconds count as 0; +inf (a time too long to represent) as the
  /// largest finite time, so such a render is never affordable again, never free.
  void measured(std::size_t i, int spp, double render_seconds, double other_seconds);

  /// The call ended: `seconds` spent inside the adapter in it (negative or NaN: 0; +inf: the
  /// largest finite time). The account's sums saturate at +-DBL_MAX: never inf, never NaN.
  void spent(double seconds);

  /// Seconds in the account: > 0 under budget (carried forward), < 0 over it (to pay back).
  double balance() const { return m_balance; }
  /// The balance the last plan() had to spend (before the call's renders).
  double allowance() const { return m_allowance; }
  /// Over the run: seconds spent inside the adapter / the simulation's seconds (0 before
  /// any simulation time).
  double ratio() const { return m_simulation > 0.0 ? m_adapter / m_simulation : 0.0; }
  double simulation_seconds() const { return m_simulation; }
  double adapter_seconds() const { return m_adapter; }
  double budget() const { return m_budget; }
  /// The learnt cost of render i at `spp` samples per pixel; < 0 while it has not rendered.
  double estimate(std::size_t i, int spp) const;

 private:
  struct Cost {
    bool known = false;
    double overhead = 0.0;  ///< seconds per render whatever its spp
    double per_spp = 0.0;   ///< seconds per sample per pixel (all views)
  };
  double m_budget;
  std::vector<BudgetLimits> m_limits;
  std::vector<Cost> m_costs;
  double m_balance = 0.0;
  double m_allowance = 0.0;
  double m_simulation = 0.0;  ///< the run's simulation seconds so far
  double m_adapter = 0.0;     ///< the run's seconds inside the adapter so far
};

}  // namespace tessera::insitu
