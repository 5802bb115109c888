// BrickCache (brick_cache.h): the brick cut, the slot layout, and the protocol between
// workers (find / acquire / enter_tile / leave_tile) and the one service thread (take_wanted
// / reserve / publish / try_flush / fail): a flush waits for quiescence, reset starts over.
#include <tessera/brick_cache.h>

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

using tessera::BrickCache;
using tessera::BrickGrid;
using tessera::DType;
using namespace std::chrono_literals;

namespace {

BrickGrid grid_10x7x5(int shift = 2) {
  const std::int64_t dims[3] = {10, 7, 5};
  return BrickGrid::make(dims, DType::Float32, shift);
}

/// Takes the wanted bricks until one comes (or a second passes).
std::vector<std::int64_t> wait_wanted(BrickCache& c) {
  std::vector<std::int64_t> out;
  for (int i = 0; i < 100 && out.empty(); ++i) c.take_wanted(out, 10ms);
  return out;
}

}  // namespace

TEST_CASE("BrickGrid: the cut, boxes and slot size", "[brick_cache]") {
  const BrickGrid g = grid_10x7x5();
  CHECK(g.edge() == 4);
  CHECK(g.bricks[0] == 3);
  CHECK(g.bricks[1] == 2);
  CHECK(g.bricks[2] == 2);
  CHECK(g.brick_count() == 12);
  CHECK(g.slot_bytes() == 64 * 4);
  CHECK(g.index(9 >> g.shift, 6 >> g.shift, 4 >> g.shift) == g.index(2, 1, 1));  // vertex (9, 6, 4)
  std::int64_t lo[3], hi[3];
  g.box(g.index(2, 1, 1), lo, hi);
  CHECK(lo[0] == 8);
  CHECK(hi[0] == 10);
  CHECK(lo[1] == 4);
  CHECK(hi[1] == 7);
  CHECK(lo[2] == 4);
  CHECK(hi[2] == 5);
  const std::int64_t bad[3] = {0, 1, 1};
  CHECK_THROWS_AS(BrickGrid::make(bad, DType::Float32, 2), std::invalid_argument);
  CHECK_THROWS_AS(BrickGrid::make(g.dims, DType::Float32, 0), std::invalid_argument);
  CHECK_THROWS_AS(BrickGrid::make(g.dims, DType::Float32, 11), std::invalid_argument);
}

TEST_CASE("BrickCache: bytes_for counts the directory and the pool", "[brick_cache]") {
  const BrickGrid g = grid_10x7x5();
  const BrickCache c(g, 3);
  CHECK(c.allocated_bytes() == BrickCache::bytes_for(g, 3));
  // pool + zero slot dominate; directory grows with the brick count, pool with the capacity
  CHECK(BrickCache::bytes_for(g, 3) >= 4 * g.slot_bytes() + 12 * 8);
  CHECK(BrickCache::bytes_for(g, 4) - BrickCache::bytes_for(g, 3) >= g.slot_bytes());
  const BrickGrid g1 = grid_10x7x5(1);  // 5x4x3 bricks of 2^3
  CHECK(BrickCache::bytes_for(g1, 1) >= static_cast<std::uint64_t>(g1.brick_count()) * 9 + 2 * g1.slot_bytes());
  CHECK_THROWS_AS(BrickCache(g, 0), std::invalid_argument);
}

TEST_CASE("BrickCache: a miss is served, a flush waits for quiescence of two workers", "[brick_cache]") {
  BrickCache c(grid_10x7x5(), 1);
  std::atomic<int> phase{0};
  std::atomic<const unsigned char*> got_a{nullptr}, got_b{nullptr};
  // Worker A: inside a tile, misses brick 0, then stays inside its tile until phase 2.
  std::thread a([&] {
    c.enter_tile();
    got_a = c.acquire(0);
    phase = 1;
    while (phase.load() < 2) std::this_thread::sleep_for(1ms);
    c.leave_tile();
  });
  auto wanted = wait_wanted(c);
  REQUIRE(wanted == std::vector<std::int64_t>{0});
  unsigned char* slot = c.reserve(0);
  REQUIRE(slot != nullptr);
  slot[0] = 42;
  c.publish(0);
  while (phase.load() < 1) std::this_thread::sleep_for(1ms);
  CHECK(got_a.load() == slot);
  CHECK(c.find(0) == slot);
  // Worker B misses brick 5: the only slot is taken, and A is still inside its tile.
  std::thread b([&] {
    c.enter_tile();
    got_b = c.acquire(5);
    c.leave_tile();
  });
  wanted = wait_wanted(c);
  REQUIRE(wanted == std::vector<std::int64_t>{5});
  CHECK(c.reserve(5) == nullptr);
  CHECK_FALSE(c.try_flush());  // A is active: pending
  CHECK(c.find(0) == slot);
  phase = 2;  // A leaves its tile: quiescent (B is blocked in acquire)
  a.join();
  std::vector<std::int64_t> none;
  c.take_wanted(none, 1s);  // returns early: the flush is possible now
  CHECK(none.empty());
  CHECK(c.try_flush());
  CHECK(c.find(0) == nullptr);
  unsigned char* slot5 = c.reserve(5);
  REQUIRE(slot5 != nullptr);
  c.publish(5);
  b.join();
  CHECK(got_b.load() == slot5);
  const auto st = c.stats();
  CHECK(st.fetched == 2);
  CHECK(st.misses == 2);
  CHECK(st.flushes == 1);
  CHECK(st.peak_resident == 1);
  // enter_tile blocks while a flush is pending
  c.enter_tile();
  CHECK(c.reserve(1) == nullptr);
  CHECK_FALSE(c.try_flush());
  std::atomic<bool> entered{false};
  std::thread late([&] {
    c.enter_tile();
    entered = true;
    c.leave_tile();
  });
  std::this_thread::sleep_for(20ms);
  CHECK_FALSE(entered.load());
  c.leave_tile();
  CHECK(c.try_flush());
  late.join();
  CHECK(entered.load());
  // reset: nothing resident, counters zero
  c.reset();
  CHECK(c.find(5) == nullptr);
  CHECK(c.stats().fetched == 0);
  CHECK(c.reserve(3) != nullptr);
}

TEST_CASE("BrickCache: fail() wakes a blocked worker with zeros", "[brick_cache]") {
  BrickCache c(grid_10x7x5(), 2);
  std::atomic<const unsigned char*> got{nullptr};
  std::thread w([&] {
    c.enter_tile();
    got = c.acquire(3);
    c.leave_tile();
  });
  REQUIRE(wait_wanted(c) == std::vector<std::int64_t>{3});
  c.fail("rank 2 is gone");
  c.fail("second reason");
  w.join();
  REQUIRE(got.load() != nullptr);
  for (std::size_t i = 0; i < c.grid().slot_bytes(); ++i) REQUIRE(got.load()[i] == 0);
  CHECK(c.failed());
  CHECK(c.failure() == "rank 2 is gone");
  c.enter_tile();  // does not block after fail()
  CHECK(c.acquire(7)[0] == 0);
  c.leave_tile();
  c.reset();
  CHECK_FALSE(c.failed());
  CHECK(c.failure().empty());
}

TEST_CASE("BrickCache: a full cache evicts the older half of its bricks, the newer stay", "[brick_cache]") {
  BrickCache c(grid_10x7x5(), 4);
  for (std::int64_t b : {7, 2, 9, 4}) {  // published in this order
    REQUIRE(c.reserve(b) != nullptr);
    c.publish(b);
  }
  CHECK(c.reserve(1) == nullptr);  // full
  REQUIRE(c.try_flush());          // no worker inside a tile: quiescent
  CHECK(c.find(7) == nullptr);
  CHECK(c.find(2) == nullptr);
  CHECK(c.find(9) != nullptr);
  CHECK(c.find(4) != nullptr);
  // Two slots free again; the next full cache evicts 9 and 4 before the bricks after them
  for (std::int64_t b : {1, 3}) {
    REQUIRE(c.reserve(b) != nullptr);
    c.publish(b);
  }
  REQUIRE(c.try_flush());
  CHECK(c.find(9) == nullptr);
  CHECK(c.find(4) == nullptr);
  CHECK(c.find(1) != nullptr);
  CHECK(c.find(3) != nullptr);
  CHECK(c.stats().flushes == 2);
}
