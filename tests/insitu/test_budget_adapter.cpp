// The render budget in the adapter (render_budget.h), under the fake clock of tests
// (TESSERA_TEST_CLOCK): the plans, the skips and their warnings, what RenderResult, the log
// and the EXR's samples channel say, and images that are the same for the same plan whatever
// the threads, and the same as an ordinary render at the planned spp.
#include "insitu_test_support.h"
#include "scoped_env.h"

#include <tessera/adapter.h>
#include <tessera/image_io.h>

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;

namespace {

constexpr int kN = 16;     // field vertices per edge
constexpr int kSize = 24;  // image edge: 576 pixels

/// A run of `calls` execute calls, steps 0, 1, ... on `threads` threads; per call the planned
/// spp of each render (0 = skipped), every result, and the last image of `main`.
struct Run {
  std::vector<std::vector<int>> spp;
  std::vector<RenderResult> results;  ///< every call's, in order
  tessera::Image last;
};

Run run(const TempDir& dir, const std::string& name, const std::string& renders, const std::string& global, int calls,
        int threads = 2) {
  std::string text = config_yaml(dir.file(name), renders, global);
  if (threads != 2) text.replace(text.find("threads: 2"), 10, "threads: " + std::to_string(threads));
  const std::string cfg = dir.write(name + ".yaml", text);
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  const tessera_grid grid = unit_grid(kN);
  Adapter a;
  a.set_quiet(true);
  REQUIRE(a.open(cfg) == TESSERA_OK);
  Run r;
  for (int c = 0; c < calls; ++c) {
    REQUIRE(a.execute(static_cast<std::int64_t>(c), 0.0, grid, {&field, 1}) == TESSERA_OK);
    std::vector<int> spp;
    for (const RenderResult& res : a.last_results()) {
      spp.push_back(res.planned_spp);
      r.results.push_back(res);
    }
    r.spp.push_back(spp);
  }
  if (const tessera::Image* img = a.last_image("main")) r.last = *img;
  REQUIRE(a.close() == TESSERA_OK);
  return r;
}

/// The test's render: `spp` at most, `min_spp` at least (with a budget).
std::string main_render(int spp, int min_spp) {
  std::string r = render_yaml("main", "", "", "density", kSize, spp);
  const std::string from = "spp: " + std::to_string(spp) + "}";
  r.replace(r.find(from), from.size(), "spp: " + std::to_string(spp) + ", min_spp: " + std::to_string(min_spp) + "}");
  return r;
}

/// What the adapter writes to stderr (its log) while `fn` runs.
template <class Fn>
std::string stderr_of(const TempDir& dir, Fn&& fn) {
  const std::string path = dir.file("stderr.txt");
  const int file = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const int saved = ::dup(STDERR_FILENO);
  REQUIRE(file >= 0);
  REQUIRE(saved >= 0);
  ::dup2(file, STDERR_FILENO);
  fn();
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  ::close(file);
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("budget under the fake clock: learns at min_spp, then plans from the samples, the same in every run",
          "[insitu][budget]") {
  // A step of the simulation is 0.01 s, a sample 1 microsecond: a spp of the 24x24 image costs
  // 0.576 ms. Budget 0.5 buys 5 ms a step: 8 spp of 32, a share of 8.68/32 floored
  tessera_test::ScopedEnv clock("TESSERA_TEST_CLOCK", std::string("0.01,1e-6"));
  TempDir dir;
  const std::string global = "  budget: 0.5\n";
  const Run a = run(dir, "a", main_render(32, 2), global, 12);
  REQUIRE(a.spp.size() == 12);
  CHECK(a.spp[0] == std::vector<int>{2});  // learns: no simulation time yet
  // Step 1: 5 ms less the first render's 1.152 ms: 3.848 ms, 6 spp; then about 8 a step
  CHECK(a.spp[1] == std::vector<int>{6});
  for (int c = 2; c < 12; ++c) {
    INFO("call " << c);
    CHECK(a.spp[c][0] >= 8);
    CHECK(a.spp[c][0] <= 9);
  }
  const RenderResult& last = a.results.back();
  CHECK(last.budget == 0.5);
  CHECK(last.actual_spp == last.planned_spp);  // no target_error: every pixel got the plan
  CHECK(last.budget_ratio <= 0.5);
  CHECK(last.budget_ratio > 0.45);
  CHECK(last.stats.samples == static_cast<std::uint64_t>(last.planned_spp) * kSize * kSize);

  // Another run, another thread count: the same plans, the same image, bit for bit
  const Run b = run(dir, "b", main_render(32, 2), global, 12, 1);
  CHECK(b.spp == a.spp);
  CHECK(same_pixels(a.last, b.last));

  // The same image as an ordinary render (no budget) at the planned spp
  const int planned = a.spp.back()[0];
  const Run plain = run(dir, "plain", main_render(planned, 1), "", 1);
  CHECK(plain.results[0].planned_spp == planned);  // without a budget: image.spp
  CHECK(plain.results[0].budget == 0.0);
  CHECK(plain.results[0].budget_ratio == 0.0);
  // (the frame number is part of the random stream: compare the same step)
  const Run plain_at = run(dir, "plain_at", main_render(planned, 1), "", 12);
  CHECK(same_pixels(a.last, plain_at.last));
}

TEST_CASE("budget: the EXR's samples channel holds what each pixel got, and target_error gets at most the plan",
          "[insitu][budget]") {
  tessera_test::ScopedEnv clock("TESSERA_TEST_CLOCK", std::string("0.01,1e-6"));
  TempDir dir;
  std::string render = main_render(64, 4);
  render.replace(render.find("min_spp: 4}"), 11, "min_spp: 4, target_error: 0.05}");
  const Run r = run(dir, "exr", render, "  budget: 0.5\n", 6);
  const RenderResult& last = r.results.back();
  REQUIRE(last.files.size() == 1);
  const tessera::Image img = tessera::read_exr(last.files[0]);
  REQUIRE(img.samples.size() == static_cast<std::size_t>(kSize) * kSize);
  double sum = 0.0;
  float most = 0.0f;
  for (float s : img.samples) {
    sum += s;
    most = std::max(most, s);
  }
  CHECK(most <= static_cast<float>(last.planned_spp));  // the plan is the most a pixel gets
  CHECK(sum / img.samples.size() == Approx(last.actual_spp));
  CHECK(last.actual_spp <= last.planned_spp);
}

TEST_CASE("budget: a render that cannot get min_spp is skipped with a warning naming the budget, no file, no failure",
          "[insitu][budget]") {
  // 1 ms of simulation a step, budget 0.1: 0.1 ms a step against 16 x 0.576 ms for min_spp 16
  tessera_test::ScopedEnv clock("TESSERA_TEST_CLOCK", std::string("0.001,1e-6"));
  TempDir dir;
  const Run r = run(dir, "skip", main_render(32, 16), "  budget: 0.1\n", 30);
  REQUIRE(r.results.size() == 30);
  CHECK(r.results[0].planned_spp == 16);  // learning
  int skipped = 0, rendered = 0;
  for (std::size_t c = 1; c < r.results.size(); ++c) {
    const RenderResult& res = r.results[c];
    CHECK(res.status == TESSERA_OK);
    if (res.budget_skipped) {
      ++skipped;
      CHECK(res.planned_spp == 0);
      CHECK(res.files.empty());
      CHECK(res.stats.samples == 0);
      REQUIRE(res.warnings.size() == 1);
      CHECK_THAT(res.warnings[0],
                 Contains("skipped: the render budget (tessera.budget = 0.1") && Contains("image.min_spp = 16"));
    } else {
      ++rendered;
      CHECK(res.planned_spp >= 16);
      CHECK(res.files.size() == 1);
    }
  }
  // 9.2 ms of debt after the learning render, 0.1 ms a step: nothing in the 29 calls after it
  CHECK(rendered == 0);
  CHECK(skipped == 29);
  CHECK(r.results.back().budget_balance < 0.0);
  CHECK(r.results.back().budget_balance == Approx(-0.009216 + 29 * 0.0001));
}

TEST_CASE("budget: the log line says the plan, what a pixel got and the account", "[insitu][budget]") {
  tessera_test::ScopedEnv clock("TESSERA_TEST_CLOCK", std::string("0.01,1e-6"));
  TempDir dir;
  const std::string cfg = dir.write("log.yaml", config_yaml(dir.file("log"), main_render(32, 2), "  budget: 0.5\n"));
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  const tessera_grid grid = unit_grid(kN);
  Adapter a;
  REQUIRE(a.open(cfg) == TESSERA_OK);
  REQUIRE(a.execute(0, 0.0, grid, {&field, 1}) == TESSERA_OK);
  tessera_status s = TESSERA_ERROR_RENDER;
  const std::string log = stderr_of(dir, [&] { s = a.execute(1, 0.0, grid, {&field, 1}); });
  REQUIRE(s == TESSERA_OK);
  INFO(log);
  CHECK_THAT(log, Contains("render 'main' step 1 (t=0): 24x24, 6 spp") &&
                      Contains("(budget 0.5: 6 of 32 spp planned, 6 a pixel on average, 0.00385 s in the account, "
                               "the run at 0.115x so far)"));
}

TEST_CASE("budget extremes on the real clock: the smallest and the largest budget, steps of microseconds",
          "[insitu][budget][robustness]") {
  tessera_test::ScopedEnv no_fake_clock("TESSERA_TEST_CLOCK", std::nullopt);
  TempDir dir;
  // 1e-300: the first call learns at min_spp, every later one is skipped; nothing divides by
  // the budget or by a simulation time of microseconds
  const Run tiny = run(dir, "tiny", main_render(8, 2), "  budget: 1e-300\n", 40);
  CHECK(tiny.results[0].planned_spp == 2);
  for (std::size_t c = 1; c < tiny.results.size(); ++c) {
    INFO("call " << c);
    CHECK(tiny.results[c].budget_skipped);
    CHECK(tiny.results[c].status == TESSERA_OK);
  }
  CHECK(std::isfinite(tiny.results.back().budget_balance));
  CHECK(tiny.results.back().budget_balance < 0.0);
  CHECK(std::isfinite(tiny.results.back().budget_ratio));
  // 1e6: whatever the calls cost, full spp after the first
  const Run huge = run(dir, "huge", main_render(8, 2), "  budget: 1000000\n", 10);
  CHECK(huge.results[0].planned_spp == 2);
  for (std::size_t c = 1; c < huge.results.size(); ++c) CHECK(huge.results[c].planned_spp == 8);
  // Steps of microseconds with a plain budget: some renders, never one with zero samples
  const Run fast = run(dir, "fast", main_render(8, 1), "  budget: 0.5\n", 200);
  int rendered = 0;
  for (const RenderResult& res : fast.results) {
    CHECK(res.status == TESSERA_OK);
    CHECK((res.budget_skipped ? res.planned_spp == 0 : res.planned_spp >= 1));
    if (!res.budget_skipped) CHECK(res.stats.samples >= static_cast<std::uint64_t>(kSize) * kSize);
    rendered += !res.budget_skipped;
  }
  CHECK(rendered >= 1);
  CHECK(std::isfinite(fast.results.back().budget_balance));
}

TEST_CASE("budget: a fake cost per sample whose product with the samples overflows is unaffordable, never free",
          "[insitu][budget][robustness]") {
  // 1e308 s a sample: the learning render's 2 x 576 samples cost +inf on the fake clock. That
  // render made, every later one is skipped (not rendered at full spp as if it cost nothing),
  // and the account stays finite
  tessera_test::ScopedEnv clock("TESSERA_TEST_CLOCK", std::string("1e300,1e308"));
  TempDir dir;
  const Run r = run(dir, "overflow", main_render(32, 2), "  budget: 0.5\n", 6);
  REQUIRE(r.results.size() == 6);
  CHECK(r.results[0].planned_spp == 2);  // learning
  for (std::size_t c = 1; c < r.results.size(); ++c) {
    INFO("call " << c);
    CHECK(r.results[c].status == TESSERA_OK);
    CHECK(r.results[c].budget_skipped);
    CHECK(r.results[c].planned_spp == 0);
    CHECK(std::isfinite(r.results[c].budget_balance));
    CHECK(std::isfinite(r.results[c].budget_ratio));
  }
}
