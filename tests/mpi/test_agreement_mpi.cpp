// Ranks that disagree fail on every rank with an error that names the rank and the value,
// never a hang and never a silent wrong image (rank_agreement.h): a config that differs on
// one rank (a trigger), an environment knob set on one rank only, a grid (spacing, origin,
// global_dims) or a step that differs on one rank at a firing call, a final-step flag on one
// rank. Run at -n 2 and -n 3; the last rank is the odd one out. Each test arms an alarm, so a
// regression that hangs kills the job (and fails the CTest entry) instead of waiting for the
// CTest timeout.
#include "agreement/rank_agreement.h"
#include "mpi_test_support.h"
#include "published_block.h"

#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

using namespace tessera_mpi_test;
namespace fs = std::filesystem;

namespace {

constexpr std::array<std::int64_t, 3> kGlobal{14, 12, 10};

/// Kills the process (and so the MPI job) if the test has not finished in 60 s.
struct Watchdog {
  Watchdog() { alarm(60); }
  ~Watchdog() { alarm(0); }
};

/// A small, fast render; `trigger` and `extra_render` vary it, `global` adds tessera: keys.
std::string config_text(const std::string& out, const std::string& trigger = "{every: 1}",
                        const std::string& extra_render = "", const std::string& global = "") {
  const std::string body =
      "    field: density\n"
      "    image: {width: 16, height: 12, spp: 1}\n"
      "    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: 3.2}}, look_at: center, fov: 30}\n"
      "    transfer_function: {range: [0, 250], density_scale: 10, opacity: [[0, 0], [1, 1]]}\n"
      "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
  std::string yaml = "tessera:\n  output_dir: " + out + "\n  threads: 1\n" + global +
                     "renders:\n  - name: view\n    trigger: " + trigger + "\n" + body;
  if (!extra_render.empty()) yaml += "  - name: " + extra_render + "\n" + body;
  return yaml;
}

/// This rank's block of the global field (float32, one ghost layer).
struct Published : PublishedBlock {
  Published() : PublishedBlock(block_of(kGlobal, {1, world_size(), 1}, world_rank()), kGlobal) {}
};

int last_rank() { return world_size() - 1; }
bool odd_one_out() { return world_rank() == last_rank(); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Seconds since `t0`.
double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("first_difference names the first differing line", "[mpi][agreement]") {
  using tessera::insitu::first_difference;
  CHECK(first_difference("a\nb\n", "a\nb\n").empty());
  CHECK(first_difference("a\n  every: 2\nc\n", "a\n  every: 1\nc\n") == "line 2: 'every: 2' vs 'every: 1'");
  CHECK(first_difference("a\n", "a\nb\n") == "line 2: end of text vs 'b'");
  const std::string long_line(500, 'x');
  CHECK(first_difference(long_line, "y").size() < 120);
}

TEST_CASE("a trigger that differs on one rank fails tessera_open on every rank", "[mpi][agreement][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  const std::string cfg =
      write_rank_config(dir, config_text(dir.file("out"), odd_one_out() ? "{every: 2}" : "{every: 1}"));
  const auto t0 = std::chrono::steady_clock::now();
  tessera_adapter* a = nullptr;
  const tessera_status s = tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a);
  const std::string error = tessera_last_error(nullptr);
  INFO(error);
  const std::string who = "rank " + std::to_string(last_rank()) + "'s effective config differs from rank 0's";
  const bool ok = s == TESSERA_ERROR_CONFIG && a == nullptr && contains(error, "ranks disagree on the config") &&
                  contains(error, who) && contains(error, "(first difference at line ") &&
                  contains(error, ": 'trigger: {every: 2}' vs 'trigger: {every: 1}'") && since(t0) < 20.0;
  CHECK(ok);
  REQUIRE(all_ranks(ok));
  if (a) tessera_close(a);
}

TEST_CASE("an environment knob set on one rank only fails tessera_open on every rank", "[mpi][agreement][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  const std::string cfg = write_rank_config(dir, config_text(dir.file("out")));
  const char* kKnob = "TESSERA_MPI_RANKS_PER_NODE";
  const char* saved = std::getenv(kKnob);
  const std::string restore = saved ? saved : "";
  unsetenv(kKnob);

  SECTION("set on the last rank only: an error naming both values, no hang in the node split") {
    if (odd_one_out()) setenv(kKnob, "1", 1);
    const auto t0 = std::chrono::steady_clock::now();
    tessera_adapter* a = nullptr;
    const tessera_status s = tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a);
    const std::string error = tessera_last_error(nullptr);
    INFO(error);
    const bool ok = s == TESSERA_ERROR_CONFIG && a == nullptr &&
                    contains(error, std::string(kKnob) + " is '1' on rank " + std::to_string(last_rank()) +
                                        " but unset on rank 0") &&
                    since(t0) < 20.0;
    CHECK(ok);
    if (a) tessera_close(a);
    REQUIRE(all_ranks(ok));
  }
  SECTION("set alike on every rank: open and a render work") {
    setenv(kKnob, "1", 1);
    Published pub;
    tessera_adapter* a = nullptr;
    tessera_status s = tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a);
    if (s == TESSERA_OK) s = tessera_execute(a, 3, 0.5, &pub.grid, &pub.field, 1);
    INFO(tessera_last_error(a));
    CHECK(s == TESSERA_OK);
    tessera_close(a);
    REQUIRE(all_ranks(s == TESSERA_OK));
  }
  if (saved) setenv(kKnob, restore.c_str(), 1);
  else unsetenv(kKnob);
}

TEST_CASE("a grid that differs on one rank fails the firing call on every rank", "[mpi][agreement][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  const std::string cfg = write_rank_config(dir, config_text(dir.file("out")));
  const std::string who = "rank " + std::to_string(last_rank());

  struct Case {
    const char* name;
    std::function<void(tessera_grid&)> change;
    std::string expected;  // in the message
  };
  const double h = 1.0 / static_cast<double>(kGlobal[0] - 1);
  const Case cases[] = {
      {"spacing", [](tessera_grid& g) { g.spacing[0] *= 0.5; },
       who + " has spacing [" + std::to_string(0.5 * h).substr(0, 6)},
      {"origin", [](tessera_grid& g) { g.origin[2] = 0.25; },
       who + " has origin [-0.5, -0.5, 0.25], rank 0 has [-0.5, -0.5, -0.5]"},
      {"global_dims", [](tessera_grid& g) { g.global_dims[0] += 1; },
       who + " has global_dims [" + std::to_string(kGlobal[0] + 1) + ", " + std::to_string(kGlobal[1]) + ", " +
           std::to_string(kGlobal[2]) + "], rank 0 has [" + std::to_string(kGlobal[0])},
      {"NaN spacing (compared bit for bit)", [](tessera_grid& g) { g.spacing[1] = std::nan(""); },
       who + " has spacing ["},
  };
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.name) {
      Published pub;
      tessera_adapter* a = nullptr;
      REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
      tessera_grid grid = pub.grid;
      if (odd_one_out()) c.change(grid);
      const auto t0 = std::chrono::steady_clock::now();
      const tessera_status s = tessera_execute(a, 3, 0.5, &grid, &pub.field, 1);
      const std::string error = tessera_last_error(a);
      INFO(error);
      INFO(c.expected);
      const bool ok = s == TESSERA_ERROR_DATA && contains(error, "ranks disagree on the grid at step 3") &&
                      contains(error, c.expected) && since(t0) < 20.0;
      CHECK(ok);
      // Nothing is left half-done: the next call with agreeing grids renders
      const tessera_status next = tessera_execute(a, 4, 0.6, &pub.grid, &pub.field, 1);
      INFO(tessera_last_error(a));
      CHECK(next == TESSERA_OK);
      tessera_close(a);
      REQUIRE(all_ranks(ok && next == TESSERA_OK));
    }
  }
}

TEST_CASE("a step that differs on one rank fails the firing call on every rank", "[mpi][agreement][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  const std::string cfg = write_rank_config(dir, config_text(dir.file("out")));
  Published pub;
  tessera_adapter* a = nullptr;
  REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
  const std::int64_t step = odd_one_out() ? 4 : 3;
  const tessera_status s = tessera_execute(a, step, 0.5, &pub.grid, &pub.field, 1);
  const std::string error = tessera_last_error(a);
  INFO(error);
  const bool ok = s == TESSERA_ERROR_DATA &&
                  contains(error, "rank " + std::to_string(last_rank()) + " is at step 4, rank 0 at step 3");
  CHECK(ok);
  tessera_close(a);
  REQUIRE(all_ranks(ok));
}

TEST_CASE("a final-step flag on one rank fails the call on every rank", "[mpi][agreement][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  const std::string out = dir.file("out");
  const std::string who = "rank " + std::to_string(last_rank());
  Published pub;

  SECTION("a render fires on one rank only") {
    const std::string cfg = write_rank_config(
        dir, config_text(out, "{every: 1}", "late\n    trigger: {at: [1000]}", "  render_final_step: true\n"));
    tessera_adapter* a = nullptr;
    REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
    const tessera_status s = odd_one_out() ? tessera_execute_final(a, 3, 0.5, &pub.grid, &pub.field, 1)
                                           : tessera_execute(a, 3, 0.5, &pub.grid, &pub.field, 1);
    const std::string error = tessera_last_error(a);
    INFO(error);
    const bool ok = s == TESSERA_ERROR_CONFIG && contains(error, "ranks disagree on which renders fire at step 3") &&
                    contains(error, "render 'late' fires on " + who + " but not on rank 0");
    CHECK(ok);
    tessera_close(a);
    REQUIRE(all_ranks(ok));
  }
  SECTION("a `when` render is forced on one rank and waits for its trigger on the others") {
    const std::string cfg =
        write_rank_config(dir, config_text(out, "{when: {above: 1000}}", "", "  render_final_step: true\n"));
    tessera_adapter* a = nullptr;
    REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
    const tessera_status s = odd_one_out() ? tessera_execute_final(a, 3, 0.5, &pub.grid, &pub.field, 1)
                                           : tessera_execute(a, 3, 0.5, &pub.grid, &pub.field, 1);
    const std::string error = tessera_last_error(a);
    INFO(error);
    const bool ok = s == TESSERA_ERROR_CONFIG && contains(error, "render 'view' is forced (final step) on " + who +
                                                                     " but waits for its `when` trigger on rank 0");
    CHECK(ok);
    tessera_close(a);
    REQUIRE(all_ranks(ok));
  }
}

TEST_CASE("ranks that agree render, and calls where nothing fires stay local", "[mpi][agreement]") {
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  const std::string cfg = write_rank_config(dir, config_text(dir.file("out"), "{every: 2}"));
  Published pub;
  tessera_adapter* a = nullptr;
  REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
  // Odd steps fire nowhere: the last rank may even make extra such calls, or pass a grid that
  // disagrees, without communication (the documented limit: those calls are not checked)
  bool ok = true;
  tessera_grid odd = pub.grid;
  if (odd_one_out()) odd.spacing[0] = 7.0;
  for (int extra = 0; extra < (odd_one_out() ? 3 : 1); ++extra)
    ok = ok && tessera_execute(a, 1, 0.1, &odd, &pub.field, 1) == TESSERA_OK;
  const tessera_status s = tessera_execute(a, 2, 0.2, &pub.grid, &pub.field, 1);
  INFO(tessera_last_error(a));
  ok = ok && s == TESSERA_OK;
  CHECK(ok);
  tessera_close(a);
  REQUIRE(all_ranks(ok));
  bool written = true;
  if (world_rank() == 0) written = fs::exists(dir.file("out/view_0002.exr"));
  REQUIRE(all_ranks(written));
}

TEST_CASE("execute_final on one rank while the others execute fails the call on every rank",
          "[mpi][agreement][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  // Every render fires at every step: forcing them changes nothing but the kind of call
  const std::string cfg =
      write_rank_config(dir, config_text(dir.file("out"), "{every: 1}", "", "  render_final_step: true\n"));
  Published pub;
  tessera_adapter* a = nullptr;
  REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
  const tessera_status s = odd_one_out() ? tessera_execute_final(a, 3, 0.5, &pub.grid, &pub.field, 1)
                                         : tessera_execute(a, 3, 0.5, &pub.grid, &pub.field, 1);
  const std::string error = tessera_last_error(a);
  INFO(error);
  bool ok = s == TESSERA_ERROR_CONFIG &&
            contains(error, "ranks disagree on the call: rank " + std::to_string(last_rank()) +
                                " called execute_final at step 3 while rank 0 called execute at step 3");
  CHECK(ok);
  // Nobody closed: the adapter goes on, and closes cleanly on every rank
  const tessera_status next = tessera_execute(a, 4, 0.6, &pub.grid, &pub.field, 1);
  INFO(tessera_last_error(a));
  CHECK(next == TESSERA_OK);
  const tessera_status closed = tessera_close(a);
  CHECK(closed == TESSERA_OK);
  ok = ok && next == TESSERA_OK && closed == TESSERA_OK;
  REQUIRE(all_ranks(ok));
}

TEST_CASE("a final call that renders on rank 0 while the others fire nothing and close: every rank reports it",
          "[mpi][agreement][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  // Nothing fires at step 3 unless forced by the final call (render_final_step)
  const std::string cfg =
      write_rank_config(dir, config_text(dir.file("out"), "{at: [1000]}", "", "  render_final_step: true\n"));
  Published pub;
  tessera_adapter* a = nullptr;
  REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
  const std::string expected =
      "ranks disagree on the call: rank 1 closed the adapter while rank 0 called execute_final at step 3";
  bool ok = true;
  if (world_rank() == 0) {
    // Its final call meets the others' close
    const tessera_status s = tessera_execute_final(a, 3, 0.5, &pub.grid, &pub.field, 1);
    const std::string error = tessera_last_error(a);
    INFO(error);
    CHECK(s == TESSERA_ERROR_CONFIG);
    CHECK_THAT(error, Catch::Matchers::Contains(expected));
    ok = s == TESSERA_ERROR_CONFIG && contains(error, expected);
    // The others have left: a later call says so without communicating, and close is local
    const tessera_status again = tessera_execute_final(a, 4, 0.6, &pub.grid, &pub.field, 1);
    INFO(tessera_last_error(a));
    CHECK(again == TESSERA_ERROR_CONFIG);
    CHECK_THAT(std::string(tessera_last_error(a)), Catch::Matchers::Contains("can only close this adapter"));
    CHECK(tessera_close(a) == TESSERA_OK);
    ok = ok && again == TESSERA_ERROR_CONFIG;
  } else {
    // Their plain call fires nothing and returns at once; their close meets rank 0's final call
    ok = tessera_execute(a, 3, 0.5, &pub.grid, &pub.field, 1) == TESSERA_OK;
    const tessera_status closed = tessera_close(a);
    const std::string error = tessera_last_error(a);
    INFO(error);
    CHECK(closed == TESSERA_ERROR_CONFIG);
    CHECK_THAT(error, Catch::Matchers::Contains(expected) && Catch::Matchers::Contains("closed all the same"));
    ok = ok && closed == TESSERA_ERROR_CONFIG && contains(error, expected);
    CHECK(tessera_close(a) == TESSERA_ERROR_CONFIG);  // closed once, whatever the agreement said
  }
  REQUIRE(all_ranks(ok));
}

TEST_CASE("a final call on rank 0 while the others go on to a firing step fails on every rank",
          "[mpi][agreement][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  const std::string cfg =
      write_rank_config(dir, config_text(dir.file("out"), "{at: [1000]}", "", "  render_final_step: true\n"));
  Published pub;
  tessera_adapter* a = nullptr;
  REQUIRE(all_ranks(tessera_open(cfg.c_str(), MPI_Comm_c2f(MPI_COMM_WORLD), &a) == TESSERA_OK));
  tessera_status s;
  if (world_rank() == 0) {
    s = tessera_execute_final(a, 3, 0.5, &pub.grid, &pub.field, 1);
  } else {
    REQUIRE(tessera_execute(a, 3, 0.5, &pub.grid, &pub.field, 1) == TESSERA_OK);  // fires nothing
    s = tessera_execute(a, 1000, 1.0, &pub.grid, &pub.field, 1);                  // fires 'view'
  }
  const std::string error = tessera_last_error(a);
  INFO(error);
  bool ok = s == TESSERA_ERROR_DATA &&
            contains(error, "ranks disagree on the step: rank 1 is at step 1000, rank 0 at step 3");
  CHECK(ok);
  const tessera_status closed = tessera_close(a);  // every rank closes: they agree
  CHECK(closed == TESSERA_OK);
  ok = ok && closed == TESSERA_OK;
  REQUIRE(all_ranks(ok));
}

TEST_CASE("a rank left waiting in the agreement says so, and keeps waiting until the others come",
          "[mpi][agreement][robustness]") {
  using tessera::insitu::CallKind;
  using tessera::insitu::CallView;
  CHECK(contains(tessera::insitu::waiting_message(2, CallView{CallKind::Final, 3, {}, {}, nullptr}, 61.2),
                 "rank 2 has waited 61 s for the other ranks in the agreement of its call (it called execute_final "
                 "at step 3)"));
  CHECK(contains(tessera::insitu::waiting_message(0, CallView{CallKind::Close, 0, {}, {}, nullptr}, 120),
                 "(it closed the adapter)"));
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_agree_");
  const std::string marker = dir.file("rank0_warned");
  auto ctx = tessera::insitu::ParallelContext::create(MPI_Comm_c2f(MPI_COMM_WORLD));
  // The other ranks join only once rank 0 has said that it waits: the order is forced, not timed
  if (world_rank() != 0)
    while (!fs::exists(marker)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  int warnings = 0;
  const int mine = 100 + world_rank();
  std::vector<int> all(static_cast<std::size_t>(world_size()), -1);
  ctx->allgather_waiting(&mine, sizeof mine, all.data(), 0.01, [&](double waited) {
    if (world_rank() == 0 && warnings == 0) std::ofstream(marker) << waited;
    ++warnings;
  });
  bool ok = world_rank() != 0 || warnings >= 1;
  for (int r = 0; r < world_size(); ++r) ok = ok && all[static_cast<std::size_t>(r)] == 100 + r;
  CHECK(ok);
  REQUIRE(all_ranks(ok));
}
