#include "budget/render_budget.h"

#include <tessera/message_text.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <vector>

namespace tessera::insitu {
namespace {

/// A finite number >= 0 filling all of `s`, or nothing.
std::optional<double> seconds_in(std::string_view s) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v) || v < 0.0) return std::nullopt;
  return v;
}

std::vector<BudgetLimits> limits_of(const config::Config& cfg) {
  std::vector<BudgetLimits> limits;
  limits.reserve(cfg.renders.size());
  for (const config::RenderSpec& r : cfg.renders) limits.push_back({r.image.spp, r.min_spp});
  return limits;
}

}  // namespace

TestClock TestClock::parse(const std::string& text) {
  const std::string_view s(text);
  const std::size_t comma = s.find(',');
  const std::optional<double> step = comma == std::string_view::npos ? std::nullopt : seconds_in(s.substr(0, comma));
  const std::optional<double> sample = comma == std::string_view::npos ? std::nullopt : seconds_in(s.substr(comma + 1));
  if (!step || !sample)
    throw std::invalid_argument(std::string(kTestClockVariable) + " is '" + shown_value(text, 60) +
                                "' (allowed: STEP_SECONDS,SAMPLE_SECONDS, two finite numbers >= 0, e.g. "
                                "\"0.01,1e-7\": the fake clock of tests, see docs/insitu.md)");
  return TestClock{*step, *sample};
}

std::optional<TestClock> TestClock::from_environment() {
  const char* v = std::getenv(kTestClockVariable);
  if (!v) return std::nullopt;
  return parse(v);
}

RenderBudget::RenderBudget(const config::Config& cfg)
    : m_planner(cfg.global.budget, limits_of(cfg)), m_clock(TestClock::from_environment()) {}

double RenderBudget::plan(std::int64_t step, double measured_simulation_seconds,
                          std::span<const unsigned char> firing) {
  // Only the simulation time not given to the planner yet: a call that planned but in which
  // nothing fired (a `when` trigger) leaves the adapter's measure running on
  double sim = 0.0;
  if (m_clock) {
    if (m_last_step && step > *m_last_step) sim = static_cast<double>(step - *m_last_step) * m_clock->step_seconds;
    m_last_step = step;  // the steps before the first call are not the simulation's time (as the real clock)
  } else {
    sim = measured_simulation_seconds - m_credited;
    m_credited = measured_simulation_seconds;
  }
  m_fake_call_seconds = 0.0;
  return m_planner.plan(sim, firing);
}

void RenderBudget::record(std::size_t i, const RenderResult& result, double pass_seconds) {
  if (result.status != TESSERA_OK || result.budget_skipped || result.planned_spp <= 0) return;
  if (m_clock) {
    const double seconds = static_cast<double>(result.stats.samples) * m_clock->sample_seconds;
    m_fake_call_seconds += seconds;
    m_planner.measured(i, result.planned_spp, seconds, 0.0);
    return;
  }
  m_planner.measured(i, result.planned_spp, result.render_seconds, std::max(0.0, pass_seconds - result.render_seconds));
}

void RenderBudget::end_call(double measured_call_seconds, std::span<RenderResult> results) {
  m_planner.spent(m_clock ? m_fake_call_seconds : measured_call_seconds);
  m_fake_call_seconds = 0.0;
  if (!results.empty()) m_credited = 0.0;  // the adapter's measure starts afresh after a call that rendered
  for (RenderResult& r : results) {
    r.budget_balance = m_planner.balance();
    r.budget_ratio = m_planner.ratio();
  }
}

}  // namespace tessera::insitu
