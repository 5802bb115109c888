#pragma once
/// RenderBudget: the adapter's side of `tessera.budget` (docs/insitu.md, "Controlling the
/// cost"). It owns the BudgetPlanner (budget_planner.h) and feeds it what the adapter
/// measures: the simulation's seconds before a call, the seconds each render took, the
/// seconds the call spent inside the adapter. Every rank keeps one; rank 0's plan is the one
/// every rank renders with (it travels in the call's agreement, rank_agreement.h).
///
/// The clock. Real (std::chrono::steady_clock, as the adapter measures simulation_seconds),
/// or for tests the fake clock of the environment variable TESSERA_TEST_CLOCK, read at open:
///   TESSERA_TEST_CLOCK="STEP_SECONDS,SAMPLE_SECONDS"   e.g. "0.01,1e-7"
/// with which the simulation takes STEP_SECONDS per step (steps since the last call that
/// rendered) and a render SAMPLE_SECONDS per sample it traced (its stats.samples: on rank 0
/// summed over ranks and Cinema views; nothing else of a call costs time). The plan then
/// depends on the config, the steps and the samples only, so it and the images are the same
/// in every run, for any number of threads or ranks. Both numbers finite and >= 0.
#include "budget/budget_planner.h"

#include <tessera/adapter.h>
#include <tessera/config/config.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace tessera::insitu {

/// The environment variable of the fake clock (also in kEnvironmentKnobs: every rank must
/// see the same value).
inline constexpr const char* kTestClockVariable = "TESSERA_TEST_CLOCK";

/// The fake clock of TESSERA_TEST_CLOCK.
struct TestClock {
  double step_seconds = 0.0;    ///< the simulation's seconds per step
  double sample_seconds = 0.0;  ///< a render's seconds per sample traced

  /// The clock `text` describes ("STEP_SECONDS,SAMPLE_SECONDS"); throws
  /// std::invalid_argument naming the variable and what is allowed.
  static TestClock parse(const std::string& text);
  /// The clock the environment asks for, or none (the variable unset).
  static std::optional<TestClock> from_environment();
};

class RenderBudget {
 public:
  /// cfg.global.budget > 0; `cfg` outlives this. Reads TESSERA_TEST_CLOCK (throws
  /// std::invalid_argument when it is set but malformed).
  explicit RenderBudget(const config::Config& cfg);

  /// Before the agreement of a call at `step` in which the renders with firing[i] != 0 fire
  /// (or may): this rank's plan (budget_planner.h). measured_simulation_seconds: the adapter's
  /// measure of the simulation's time since the last call that rendered.
  double plan(std::int64_t step, double measured_simulation_seconds, std::span<const unsigned char> firing);

  /// After render i of the call ran (not skipped, not failed): `pass_seconds` is the wall
  /// time the whole render took here, `result` what it reports (planned_spp,
  /// render_seconds, stats.samples).
  void record(std::size_t i, const RenderResult& result, double pass_seconds);

  /// The call ended after `measured_call_seconds` inside execute: the account is settled
  /// and written into each result (budget_balance, budget_ratio). `results` empty: nothing
  /// fired (the adapter's simulation clock runs on).
  void end_call(double measured_call_seconds, std::span<RenderResult> results);

  /// The balance this call's plan had to spend (seconds), for the log line.
  double allowance() const { return m_planner.allowance(); }
  /// The run's ratio so far (seconds inside the adapter / the simulation's seconds).
  double ratio() const { return m_planner.ratio(); }
  double budget() const { return m_planner.budget(); }
  bool fake_clock() const { return m_clock.has_value(); }

 private:
  BudgetPlanner m_planner;
  std::optional<TestClock> m_clock;
  std::optional<std::int64_t> m_last_step;  ///< fake clock: the step of the last plan
  double m_credited = 0.0;           ///< real clock: of the adapter's simulation seconds, those planned with already
  double m_fake_call_seconds = 0.0;  ///< fake clock: this call's renders so far
};

}  // namespace tessera::insitu
