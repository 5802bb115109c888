// BudgetPlanner (insitu/src/budget_planner.h): the plan of each call under tessera.budget,
// driven here by a fake clock (a cost model of seconds = overhead + per_spp x spp and a fixed
// simulation time per call), so that every figure is exact and the same in every run.
#include "budget/budget_planner.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using namespace tessera::insitu;

namespace {

/// What one render costs under the fake clock.
struct FakeCost {
  double overhead = 0.0;
  double per_spp = 0.0;
  double at(int spp) const { return overhead + per_spp * spp; }
};

/// One call of a simulation whose renders all fire: plan, render (at the fake cost, times
/// `noise`), settle. Returns the planned spp per render (0 = skipped).
std::vector<int> call(BudgetPlanner& p, const std::vector<BudgetLimits>& limits, const std::vector<FakeCost>& cost,
                      double sim_seconds, double noise = 1.0) {
  const std::vector<unsigned char> firing(limits.size(), 1);
  const double plan = p.plan(sim_seconds, firing);
  std::vector<int> spp(limits.size());
  double spent = 0.0;
  for (std::size_t i = 0; i < limits.size(); ++i) {
    spp[i] = planned_spp(plan, limits[i]);
    REQUIRE(spp[i] >= 0);
    REQUIRE(spp[i] <= limits[i].spp);
    if (spp[i] == 0) continue;
    REQUIRE(spp[i] >= limits[i].min_spp);  // never fewer samples than min_spp, never zero
    const double render = cost[i].per_spp * spp[i] * noise, other = cost[i].overhead * noise;
    p.measured(i, spp[i], render, other);
    spent += render + other;
  }
  p.spent(spent);
  return spp;
}

}  // namespace

TEST_CASE("planned_spp: a share of spp, floored, skipped below min_spp, the same for the same bits",
          "[insitu][budget]") {
  const BudgetLimits l{64, 4};
  CHECK(planned_spp(1.0, l) == 64);
  CHECK(planned_spp(std::numeric_limits<double>::infinity(), l) == 64);
  CHECK(planned_spp(0.5, l) == 32);
  CHECK(planned_spp(0.49, l) == 31);     // floor(31.36)
  CHECK(planned_spp(4.0 / 64, l) == 4);  // exactly min_spp
  CHECK(planned_spp(std::nextafter(4.0 / 64, 0.0), l) == 0);
  CHECK(planned_spp(0.0, l) == 0);
  CHECK(planned_spp(kLearnPlan, l) == 4);  // learning: min_spp
  CHECK(planned_spp(-1e300, l) == 4);
  CHECK(planned_spp(std::nan(""), l) == 0);
  CHECK(planned_spp(0.99, BudgetLimits{1, 1}) == 0);  // a share of one sample is no sample
  CHECK(planned_spp(1.0, BudgetLimits{1, 1}) == 1);
  CHECK(planned_spp(0.5, BudgetLimits{1 << 20, 1}) == 1 << 19);
}

TEST_CASE("the first call learns at min_spp, then the plan follows what was measured", "[insitu][budget]") {
  const std::vector<BudgetLimits> limits{{64, 2}};
  const std::vector<FakeCost> cost{{0.01, 0.001}};
  BudgetPlanner p(0.25, limits);
  // No simulation time before the first call and nothing measured: min_spp, the account in debt
  CHECK(call(p, limits, cost, 0.0) == std::vector<int>{2});
  CHECK(p.balance() == Approx(-cost[0].at(2)));
  CHECK(p.estimate(0, 10) == Approx(cost[0].at(10)));
  // 0.2 s of simulation buy 0.05 s: the debt (0.012 s) first, then (0.038 - 0.01) / 0.064 of 64 spp
  CHECK(call(p, limits, cost, 0.2) == std::vector<int>{28});
  // 0.4 s buy 0.1 s, more than 64 spp cost (0.074 s): full spp, and no credit beyond one call's cost
  CHECK(call(p, limits, cost, 0.4) == std::vector<int>{64});
  CHECK(p.balance() == Approx(0.0).margin(1e-12));
  for (int c = 0; c < 10; ++c) CHECK(call(p, limits, cost, 0.4) == std::vector<int>{64});
  CHECK(p.balance() == Approx(0.0).margin(1e-12));
}

TEST_CASE("with a fake clock the account converges to the budget over many calls", "[insitu][budget]") {
  const std::vector<BudgetLimits> limits{{256, 1}, {64, 1}};
  const std::vector<FakeCost> cost{{0.004, 0.0005}, {0.02, 0.003}};  // a single view and a Cinema sweep
  for (const double budget : {0.05, 0.25, 1.0}) {
    INFO("budget " << budget);
    BudgetPlanner p(budget, limits);
    std::uint32_t rng = 12345;  // render times vary by +-20% (deterministic)
    std::vector<int> last;
    for (int c = 0; c < 400; ++c) {
      rng = rng * 1664525u + 1013904223u;
      const double noise = 0.8 + 0.4 * (rng >> 8) / double(1u << 24);
      last = call(p, limits, cost, 0.2, noise);
    }
    // Every budget here affords more than min_spp and less than full spp: the account is spent
    CHECK(p.ratio() <= budget * 1.01);
    CHECK(p.ratio() >= budget * 0.95);
    CHECK(last[0] > 1);
    CHECK(last[0] < 256);
    CHECK(std::fabs(p.balance()) < cost[0].at(256) + cost[1].at(64));
  }
}

TEST_CASE("a budget that cannot give min_spp skips renders, never renders late, and renders again once paid",
          "[insitu][budget]") {
  const std::vector<BudgetLimits> limits{{16, 4}};
  const std::vector<FakeCost> cost{{0.002, 0.001}};  // 6 ms at min_spp
  BudgetPlanner p(0.01, limits);                     // 1 ms a call of 0.1 s
  int rendered = 0, skipped = 0;
  for (int c = 0; c < 600; ++c) {
    const int spp = call(p, limits, cost, 0.1)[0];
    if (spp == 0) {
      ++skipped;
      continue;
    }
    ++rendered;
    if (c > 0) CHECK(p.balance() >= -1e-12);  // after the first call a render is always paid for
    CHECK(spp >= 4);
  }
  // About one call in six renders, at min_spp (4 spp cost 6 ms; 1 ms a call)
  CHECK(rendered >= 95);
  CHECK(rendered <= 101);
  CHECK(skipped == 600 - rendered);
  CHECK(p.ratio() <= 0.01 * 1.001);
  CHECK(p.ratio() >= 0.0095);
}

TEST_CASE("steps of microseconds, or no time at all, plan sanely: finite figures, no zero-sample render",
          "[insitu][budget]") {
  const std::vector<BudgetLimits> limits{{8, 1}};
  const std::vector<FakeCost> cost{{0.001, 0.002}};
  for (const double step : {0.0, 1e-9, 1e-6}) {
    INFO("simulation seconds per call " << step);
    BudgetPlanner p(0.5, limits);
    int rendered = 0;
    for (int c = 0; c < 10000; ++c) rendered += call(p, limits, cost, step)[0] > 0;
    CHECK(rendered >= 1);  // the first call measures
    CHECK(rendered <= 2);  // then 3 ms of debt against at most 5 ms of budget in all
    CHECK(std::isfinite(p.balance()));
    CHECK(std::isfinite(p.ratio()));
    CHECK(p.ratio() >= 0.0);
  }
  // Nonsense times count as nothing
  BudgetPlanner p(0.5, limits);
  const std::vector<unsigned char> fire{1};
  CHECK(p.plan(std::nan(""), fire) == kLearnPlan);
  p.measured(0, 1, -5.0, std::nan(""));
  p.spent(std::nan(""));
  CHECK(p.balance() == 0.0);
  CHECK(p.estimate(0, 8) == 0.0);
  // A render that costs nothing measurable: full spp whenever the account is not in debt
  CHECK(p.plan(-1.0, fire) == 1.0);
  p.spent(1e-3);
  CHECK(p.plan(1e-3, fire) == 0.0);  // 0.5 ms against 1 ms of debt: skipped
  CHECK(p.plan(1e-3, fire) == 1.0);  // paid
}

TEST_CASE("a render firing for the first time learns when the account allows, not while it is in debt",
          "[insitu][budget]") {
  const std::vector<BudgetLimits> limits{{32, 2}, {32, 3}};
  BudgetPlanner p(0.1, limits);
  const std::vector<unsigned char> first{1, 0}, both{1, 1};
  CHECK(p.plan(0.0, first) == kLearnPlan);
  p.measured(0, 2, 0.02, 0.0);
  p.spent(0.02);
  // The second render fires while the account is 20 ms in debt: nobody renders
  CHECK(p.plan(0.1, both) == 0.0);
  p.spent(0.0);
  CHECK(p.plan(0.1, both) == kLearnPlan);  // 20 ms of debt paid: learn, every render at min_spp
  CHECK(planned_spp(kLearnPlan, limits[0]) == 2);
  CHECK(planned_spp(kLearnPlan, limits[1]) == 3);
}

TEST_CASE("an account that pays for full spp gives full spp, whatever the rounding of the costs", "[insitu][budget]") {
  // Costs whose sum and difference round: (overhead + per_share - overhead) / per_share < 1
  const std::vector<BudgetLimits> limits{{8, 1}, {7, 1}};
  const std::vector<FakeCost> cost{{0.1, 0.0001 / 3}, {0.3, 0.0007 / 9}};
  BudgetPlanner p(1e6, limits);
  call(p, limits, cost, 0.0);
  for (int c = 0; c < 50; ++c) CHECK(call(p, limits, cost, 1e-6 * (c + 1)) == std::vector<int>{8, 7});
}

TEST_CASE("one share for every render of a call: cheap and costly renders keep the same fraction of spp",
          "[insitu][budget]") {
  // Costs and times that are binary fractions: every figure below is exact
  const std::vector<BudgetLimits> limits{{128, 1}, {16, 8}};
  const std::vector<FakeCost> cost{{0.0, 1.0 / 1024}, {0.0, 1.0 / 64}};  // 0.125 s and 0.25 s at full spp
  BudgetPlanner p(1.0, limits);
  CHECK(call(p, limits, cost, 0.0) == std::vector<int>{1, 8});  // learns at min_spp: 129/1024 s of debt
  CHECK(p.balance() == -129.0 / 1024);
  // The debt and 0.375 s: a share of 1
  CHECK(call(p, limits, cost, 129.0 / 1024 + 0.375) == std::vector<int>{128, 16});
  CHECK(p.balance() == 0.0);
  // Half of it: half of each render's spp (the second at its min_spp)
  CHECK(call(p, limits, cost, 0.1875) == std::vector<int>{64, 8});
  // A quarter: 32 spp and 4 < min_spp 8: the second is skipped, the time it leaves carried forward
  CHECK(call(p, limits, cost, 0.09375) == std::vector<int>{32, 0});
  CHECK(p.balance() == 0.0625);
}

TEST_CASE("a cost too large to represent is the largest cost, never a free render", "[insitu][budget]") {
  // A fake clock's seconds per sample times a sample count can overflow to +inf: such a render
  // (or call) must count as unaffordable, and the account must stay finite (no inf, no NaN)
  const double inf = std::numeric_limits<double>::infinity();
  const double huge = std::numeric_limits<double>::max();
  const std::vector<BudgetLimits> limits{{8, 1}};
  const std::vector<unsigned char> fire{1};
  for (const int which : {0, 1, 2}) {
    INFO((which == 0 ? "render seconds" : which == 1 ? "other seconds" : "call seconds") << " +inf");
    BudgetPlanner p(0.5, limits);
    CHECK(p.plan(0.0, fire) == kLearnPlan);
    p.measured(0, 1, which == 0 ? inf : 1e-3, which == 1 ? inf : 0.0);
    p.spent(which == 2 ? inf : 1e-3);
    CHECK(std::isfinite(p.balance()));
    CHECK(std::isfinite(p.ratio()));
    if (which < 2) CHECK(p.estimate(0, 8) >= huge);  // not 0: the old reading made it free
    // A simulation step of any finite length never pays for it
    for (const double sim : {1.0, 1e6, 1e300}) {
      INFO("simulation seconds " << sim);
      const double plan = p.plan(sim, fire);
      CHECK(planned_spp(plan, limits[0]) == 0);
      p.spent(0.0);
      CHECK(std::isfinite(p.balance()));
      CHECK(std::isfinite(p.ratio()));
    }
  }
  // A simulation time that overflows is the largest time, not nothing, and leaves no NaN
  BudgetPlanner q(2.0, limits);
  CHECK(q.plan(inf, fire) == kLearnPlan);
  CHECK(std::isfinite(q.balance()));
  q.measured(0, 8, 1e-3, 0.0);
  q.spent(inf);
  CHECK(std::isfinite(q.balance()));
  CHECK(q.ratio() > 0.0);
  CHECK(std::isfinite(q.ratio()));
}
