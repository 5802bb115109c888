// The render budget across ranks (render_budget.h): every rank renders with rank 0's plan,
// carried in the call's agreement, even when its own clock would plan otherwise; ranks that
// disagree on the budget, on min_spp or on the fake clock fail tessera_open; under the fake
// clock (TESSERA_TEST_CLOCK) the plan is the one a BudgetPlanner computes from the samples
// alone, on any number of ranks. Run at -n 2 and -n 3. Each test arms an alarm, so a
// regression that hangs (a rank skipping while another renders) kills the job.
#include "budget/budget_planner.h"
#include "mpi_test_support.h"
#include "published_block.h"
#include "scoped_env.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

using namespace tessera_mpi_test;
using tessera::insitu::Adapter;
using tessera::insitu::RenderResult;
using EnvVar = tessera_test::ScopedEnv;

namespace {

constexpr std::array<std::int64_t, 3> kGlobal{14, 12, 10};
constexpr int kWidth = 16, kHeight = 12;

struct Watchdog {
  Watchdog() { alarm(90); }
  ~Watchdog() { alarm(0); }
};

/// One render (or two) fired every step, `spp` at most, with `global` tessera: keys.
std::string budget_config(const std::string& out, const std::string& global, int spp, int min_spp,
                          bool two_renders = false) {
  const std::string body =
      "    field: density\n"
      "    image: {width: " +
      std::to_string(kWidth) + ", height: " + std::to_string(kHeight) + ", spp: " + std::to_string(spp) +
      ", min_spp: " + std::to_string(min_spp) +
      "}\n"
      "    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: 3.2}}, look_at: center, fov: 30}\n"
      "    transfer_function: {range: [0, 250], density_scale: 10, opacity: [[0, 0], [1, 1]]}\n"
      "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
  std::string yaml = "tessera:\n  output_dir: " + out + "\n" + global + "renders:\n  - name: view\n" + body;
  if (two_renders) yaml += "  - name: other\n" + body;
  return yaml;
}

/// This rank's block of the global field (float32, one ghost layer).
struct Published : PublishedBlock {
  Published() : PublishedBlock(block_of(kGlobal, {1, world_size(), 1}, world_rank()), kGlobal) {}
};

/// `value` on every rank, as rank 0 has it (so each rank can compare its own).
int rank0_value(int value) {
  MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return value;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("every rank renders with rank 0's plan, whatever its own clock says", "[mpi][budget]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  EnvVar no_fake_clock("TESSERA_TEST_CLOCK", std::nullopt);
  SharedTempDir dir("tessera_budget_");
  const std::string cfg = write_rank_config(dir, budget_config(dir.file("out"), "  threads: 1\n  budget: 1\n", 64, 1));
  Published pub;
  Adapter a;
  a.set_quiet(true);
  REQUIRE(all_ranks(a.open(cfg, MPI_Comm_c2f(MPI_COMM_WORLD)) == TESSERA_OK));
  const auto run = [&](std::int64_t step, bool others_sleep, double seconds) {
    // The sleeping ranks simulate; the others wait for them inside execute (the adapter's time)
    if ((world_rank() != 0) == others_sleep) std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    const tessera_status s = a.execute(step, 0.1 * static_cast<double>(step), pub.grid, {&pub.field, 1});
    REQUIRE(all_ranks(s == TESSERA_OK && a.last_results().size() == 1));
    return a.last_results()[0];
  };

  // The first call learns: min_spp everywhere. Rank 0 waits 1 s for the others in it: its
  // account is 1 s in debt, theirs hardly
  CHECK(run(0, true, 1.0).planned_spp == 1);

  // The others simulate 0.5 s (their own accounts could pay for a render); rank 0, in debt,
  // skips, and so does every rank
  const RenderResult skipped = run(1, true, 0.5);
  CHECK(skipped.planned_spp == 0);
  CHECK(skipped.budget_skipped);
  CHECK(skipped.files.empty());
  CHECK(all_ranks(skipped.planned_spp == rank0_value(skipped.planned_spp)));

  // Rank 0 simulates 4 s: its debt (1.5 s) paid with 2.5 s to spare, it plans full spp (64
  // samples of this small image cost well under that even on a loaded machine: with 2 s, a
  // machine at load 6 planned 39), and every rank renders it
  const RenderResult rendered = run(2, false, 4.0);
  INFO("planned " << rendered.planned_spp << " on rank " << world_rank());
  CHECK(all_ranks(rendered.planned_spp == rank0_value(rendered.planned_spp)));
  CHECK(rank0_value(rendered.planned_spp) == 64);
  CHECK(rendered.status == TESSERA_OK);
  CHECK_FALSE(rendered.budget_skipped);
  // Rank 0's stats are summed over ranks: had a rank traced another spp for its tiles, the
  // sum would not be the plan's
  if (world_rank() == 0) {
    CHECK(rendered.stats.samples == static_cast<std::uint64_t>(rendered.planned_spp) * kWidth * kHeight);
    CHECK(rendered.actual_spp == rendered.planned_spp);
    CHECK(rendered.files.size() == 1);
  }
  REQUIRE(all_ranks(a.close() == TESSERA_OK));
}

TEST_CASE("under the fake clock the plans are a BudgetPlanner's over the samples, on any number of ranks",
          "[mpi][budget]") {
  Watchdog watchdog;
  // 0.05 s of simulation per step, 2 microseconds per sample: 192 samples per spp of one
  // render cost 0.384 ms, so budget 0.02 buys 2 ms a call of two steps: 2.6 spp for each of two
  // renders, below their min_spp of 4 one call in three
  EnvVar fake_clock("TESSERA_TEST_CLOCK", "0.05,2e-6");
  SharedTempDir dir("tessera_budget_fake_");
  const std::string cfg =
      write_rank_config(dir, budget_config(dir.file("out"), "  threads: 2\n  budget: 0.02\n", 32, 4, true));
  Published pub;
  Adapter a;
  a.set_quiet(true);
  REQUIRE(all_ranks(a.open(cfg, MPI_Comm_c2f(MPI_COMM_WORLD)) == TESSERA_OK));

  // The same sequence from the planner alone, fed the samples the renders trace (spp x pixels)
  tessera::insitu::BudgetPlanner expected(0.02, {{32, 4}, {32, 4}});
  const std::vector<unsigned char> both{1, 1};
  int rendered = 0, skipped = 0;
  for (std::int64_t step = 0; step < 40; step += 2) {  // a call every other step
    const double plan = expected.plan(step == 0 ? 0.0 : 2 * 0.05, both);
    double spent = 0.0;
    std::vector<int> want;
    for (std::size_t i = 0; i < 2; ++i) {
      const int spp = tessera::insitu::planned_spp(plan, {32, 4});
      want.push_back(spp);
      if (spp == 0) continue;
      const double seconds = static_cast<double>(spp) * kWidth * kHeight * 2e-6;
      expected.measured(i, spp, seconds, 0.0);
      spent += seconds;
    }
    expected.spent(spent);

    REQUIRE(all_ranks(a.execute(step, 0.0, pub.grid, {&pub.field, 1}) == TESSERA_OK));
    REQUIRE(a.last_results().size() == 2);
    for (std::size_t i = 0; i < 2; ++i) {
      const RenderResult& r = a.last_results()[i];
      INFO("step " << step << ", render " << i);
      CHECK(r.planned_spp == want[i]);
      CHECK(r.budget_skipped == (want[i] == 0));
      (want[i] ? rendered : skipped) += 1;
      if (world_rank() == 0 && want[i] > 0)
        CHECK(r.stats.samples == static_cast<std::uint64_t>(want[i]) * kWidth * kHeight);
      if (world_rank() == 0) {
        CHECK(r.budget_balance == expected.balance());
        CHECK(r.budget_ratio == expected.ratio());
      }
    }
  }
  // The budget bought some renders and skipped others, and the account kept it
  CHECK(rendered > 4);
  CHECK(skipped > 4);
  CHECK(expected.ratio() <= 0.02);
  REQUIRE(all_ranks(a.close() == TESSERA_OK));
}

TEST_CASE("ranks that disagree on the budget, min_spp or the fake clock fail tessera_open",
          "[mpi][budget][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  const bool odd = world_rank() == world_size() - 1;
  const std::string last = "rank " + std::to_string(world_size() - 1);
  SharedTempDir dir("tessera_budget_open_");
  const auto open_error = [&](const std::string& text) {
    const std::string cfg = write_rank_config(dir, text);
    Adapter a;
    const tessera_status s = a.open(cfg, MPI_Comm_c2f(MPI_COMM_WORLD));
    return s == TESSERA_ERROR_CONFIG ? a.last_error() : std::string("opened (status ") + std::to_string(s) + ")";
  };
  const std::string out = dir.file("out");

  std::string e = open_error(budget_config(out, odd ? "  budget: 0.3\n" : "  budget: 0.25\n", 16, 1));
  INFO(e);
  CHECK(all_ranks(contains(e, "ranks disagree on the config") && contains(e, last) &&
                  contains(e, "'budget: 0.3' vs 'budget: 0.25'")));
  e = open_error(budget_config(out, odd ? "" : "  budget: 0.25\n", 16, 1));  // a budget on some ranks only
  CHECK(all_ranks(contains(e, "ranks disagree on the config")));
  e = open_error(budget_config(out, "  budget: 0.25\n", 16, odd ? 2 : 1));
  CHECK(all_ranks(contains(e, "ranks disagree on the config") && contains(e, "min_spp: 2")));
  {
    EnvVar clock("TESSERA_TEST_CLOCK", std::string(odd ? "0.1,1e-6" : "0.1,2e-6"));
    e = open_error(budget_config(out, "  budget: 0.25\n", 16, 1));
    CHECK(all_ranks(contains(e, "ranks disagree on the environment") &&
                    contains(e, "TESSERA_TEST_CLOCK is '0.1,1e-6' on " + last)));
  }
  {
    EnvVar clock("TESSERA_TEST_CLOCK", "0.1;1e-6");  // malformed on every rank: a clear error everywhere
    e = open_error(budget_config(out, "  budget: 0.25\n", 16, 1));
    CHECK(all_ranks(contains(e, "TESSERA_TEST_CLOCK is '0.1;1e-6' (allowed: STEP_SECONDS,SAMPLE_SECONDS")));
  }
}
