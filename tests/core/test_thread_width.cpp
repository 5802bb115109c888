// The thread width rules shared by the renderer and the adapter (tessera/thread_width.h and
// insitu's rank_threads): every request, however absurd, lands in [1, TBB's cap], and the
// runner's arena is exactly that wide.
#include "parallel/rank_threads.h"

#include <tessera/thread_width.h>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <catch2/catch.hpp>

#include <climits>
#include <stdexcept>

TEST_CASE("thread widths are clamped to TBB's cap and never below one", "[threads]") {
  const tbb::global_control cap(tbb::global_control::max_allowed_parallelism, 2);
  CHECK(tessera::thread_cap() == 2);
  CHECK(tessera::clamp_threads(65536) == 2);
  CHECK(tessera::clamp_threads(INT_MAX) == 2);
  CHECK(tessera::clamp_threads(1) == 1);
  CHECK(tessera::clamp_threads(-7) >= 1);
  CHECK(tessera::clamp_threads(-7) <= 2);
  // the adapter's rule: tessera.threads over the cap lands on the cap; a node's share is >= 1
  CHECK(tessera::insitu::rank_threads(65536, 1) == 2);
  CHECK(tessera::insitu::rank_threads(65536, 64) == 2);
  CHECK(tessera::insitu::rank_threads(1, 1) == 1);
  CHECK(tessera::insitu::rank_threads(0, 1 << 20) >= 1);
  CHECK(tessera::insitu::rank_threads(INT_MIN, 3) >= 1);
}

TEST_CASE("within_threads runs in an arena exactly as wide as asked, within the cap", "[threads]") {
  const tbb::global_control cap(tbb::global_control::max_allowed_parallelism, 2);
  CHECK(tessera::within_threads(1, [] { return tbb::this_task_arena::max_concurrency(); }) == 1);
  CHECK(tessera::within_threads(65536, [] { return tbb::this_task_arena::max_concurrency(); }) <= 2);
  // nested: a one-thread pass inside a wider one is still one thread wide
  const int nested = tessera::within_threads(
      2, [] { return tessera::within_threads(1, [] { return tbb::this_task_arena::max_concurrency(); }); });
  CHECK(nested == 1);
  // results and exceptions pass through
  CHECK(tessera::within_threads(1, [] { return 42; }) == 42);
  CHECK_THROWS_AS(tessera::within_threads(1, []() -> int { throw std::runtime_error("x"); }), std::runtime_error);
}
