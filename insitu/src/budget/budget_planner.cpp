#include "budget/budget_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace tessera::insitu {
namespace {

constexpr double kMaxSeconds = std::numeric_limits<double>::max();

/// Seconds as measured: 0 when they make no sense (a clock that went back, NaN); a time too
/// long to represent (+inf: a fake clock's seconds per sample times a sample count that
/// overflows, say) as the largest finite one, so that it stays the most costly time there
/// is, never a free one.
double sane(double seconds) { return seconds > 0.0 ? std::min(seconds, kMaxSeconds) : 0.0; }

/// a + b for the account's sums, saturating at +-kMaxSeconds: the account never holds an
/// infinity (whose differences would be NaN).
double saturated_sum(double a, double b) { return std::clamp(a + b, -kMaxSeconds, kMaxSeconds); }

}  // namespace

int planned_spp(double plan, const BudgetLimits& limits) {
  const int spp = std::max(1, limits.spp);
  const int min_spp = std::clamp(limits.min_spp, 1, spp);
  if (std::isnan(plan)) return 0;
  if (plan < 0.0) return min_spp;
  if (plan >= 1.0) return spp;
  // floor(plan x spp) < spp for plan < 1: the product of two doubles, the same on every rank
  const int n = static_cast<int>(std::floor(plan * static_cast<double>(spp)));
  return n >= min_spp ? std::min(n, spp) : 0;
}

BudgetPlanner::BudgetPlanner(double budget, std::vector<BudgetLimits> renders)
    : m_budget(budget > 0.0 ? budget : std::numeric_limits<double>::denorm_min()),
      m_limits(std::move(renders)),
      m_costs(m_limits.size()) {}

double BudgetPlanner::plan(double simulation_seconds, std::span<const unsigned char> firing) {
  const double sim = sane(simulation_seconds);
  m_simulation = saturated_sum(m_simulation, sim);
  m_balance = saturated_sum(m_balance, m_budget * sim);
  m_allowance = m_balance;

  // Nothing learnt yet for a firing render: learn at min_spp, unless paying back a debt
  double overhead = 0.0, per_share = 0.0;  // the call's cost at share f: overhead + f x per_share
  bool learning = false, any = false;
  const std::size_t n = std::min(firing.size(), m_costs.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!firing[i]) continue;
    any = true;
    if (!m_costs[i].known) {
      learning = true;
      continue;
    }
    overhead = saturated_sum(overhead, m_costs[i].overhead);
    per_share = saturated_sum(per_share, m_costs[i].per_spp * static_cast<double>(std::max(1, m_limits[i].spp)));
  }
  if (!any) return 1.0;
  if (learning) return m_balance >= 0.0 ? kLearnPlan : 0.0;

  // Credit carried forward: at most what this call could spend at full spp (which it gets,
  // without the rounding of (balance - overhead) / per_share)
  const double full = saturated_sum(overhead, per_share);
  if (m_balance >= full) {
    m_balance = full;
    m_allowance = m_balance;
    return 1.0;
  }

  // The share the balance pays for (renders that cost nothing per sample: all or nothing)
  const double left = m_balance - overhead;
  if (!(per_share > 0.0)) return left >= 0.0 ? 1.0 : 0.0;
  if (!(left > 0.0)) return 0.0;
  const double f = left / per_share;
  return f >= 1.0 ? 1.0 : f;  // f > 0 and finite here
}

void BudgetPlanner::measured(std::size_t i, int spp, double render_seconds, double other_seconds) {
  if (i >= m_costs.size() || spp <= 0) return;
  const double per_spp = sane(render_seconds) / static_cast<double>(spp);
  const double overhead = sane(other_seconds);
  Cost& c = m_costs[i];
  if (!c.known) {
    c = Cost{true, overhead, per_spp};
    return;
  }
  c.overhead = 0.5 * c.overhead + 0.5 * overhead;  // (halves first: no overflow near kMaxSeconds)
  c.per_spp = 0.5 * c.per_spp + 0.5 * per_spp;
}

void BudgetPlanner::spent(double seconds) {
  const double s = sane(seconds);
  m_adapter = saturated_sum(m_adapter, s);
  m_balance = saturated_sum(m_balance, -s);
}

double BudgetPlanner::estimate(std::size_t i, int spp) const {
  if (i >= m_costs.size() || !m_costs[i].known) return -1.0;
  return saturated_sum(m_costs[i].overhead, m_costs[i].per_spp * static_cast<double>(std::max(0, spp)));
}

}  // namespace tessera::insitu
