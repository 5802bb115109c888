// Robustness: races a simulation can hit on one adapter. Closing it while another thread is
// inside execute waits for that call (no use after free); calls that overlap, or that arrive
// while a close waits or runs, are refused with a message. Run under ASan by
// scripts/sanitize.sh: a use after free there fails the test even when it does not crash.
#include "../insitu/insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <atomic>
#include <span>
#include <string>
#include <thread>
#include <vector>

using namespace tessera::insitu::test;
using Catch::Matchers::Contains;

namespace {

constexpr int kN = 8;        ///< grid vertices per axis
constexpr int kRounds = 12;  ///< open / race / close rounds per test

std::string small_config(TempDir& dir) {
  return dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "", "", "density", 8, 1)));
}

/// Spins until `count` reaches `at_least` (the other thread has started that many calls).
void wait_for(const std::atomic<int>& count, int at_least) {
  while (count.load() < at_least) std::this_thread::yield();
}

bool refused_or_closed(const std::string& message) {
  return message.find("adapter is being closed") != std::string::npos ||
         message.find("adapter was closed") != std::string::npos;
}

}  // namespace

TEST_CASE("close race: tessera_close while another thread is inside tessera_execute waits for it",
          "[robustness][handles][race]") {
  TempDir dir;
  const std::string cfg = small_config(dir);
  const std::vector<float> v = to_float(blob_values(kN));
  const tessera_field f = dense_field("density", v.data(), kN);
  const tessera_grid g = unit_grid(kN);
  for (int round = 0; round < kRounds; ++round) {
    tessera_adapter* a = nullptr;
    REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
    std::atomic<int> started{0};
    tessera_status last = TESSERA_OK;
    std::string message;
    int ok = 0;
    std::thread sim([&] {
      // Executes (every call renders) until the adapter refuses: it was closed meanwhile
      for (std::int64_t step = 0;; ++step) {
        started.fetch_add(1);
        last = round % 2 ? tessera_execute_final(a, step, 0.0, &g, &f, 1) : tessera_execute(a, step, 0.0, &g, &f, 1);
        if (last != TESSERA_OK) {
          message = tessera_last_error(a);
          break;
        }
        ++ok;
      }
    });
    wait_for(started, 2);
    const tessera_status closed = tessera_close(a);
    sim.join();
    CHECK(closed == TESSERA_OK);
    CHECK(ok >= 1);
    CHECK(last == TESSERA_ERROR_CONFIG);
    CHECK(refused_or_closed(message));
    CHECK_THAT(std::string(tessera_last_error(a)), Contains("adapter was closed"));
  }
}

TEST_CASE("close race: overlapping calls on one handle are refused and two closes at once close once",
          "[robustness][handles][race]") {
  TempDir dir;
  const std::string cfg = small_config(dir);
  const std::vector<float> v = to_float(blob_values(kN));
  const tessera_field f = dense_field("density", v.data(), kN);
  const tessera_grid g = unit_grid(kN);
  for (int round = 0; round < kRounds; ++round) {
    tessera_adapter* a = nullptr;
    REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
    std::atomic<int> started{0};
    std::atomic<int> bad{0};  // a status or message other than the contract's
    const auto executor = [&] {
      for (std::int64_t step = 0;; ++step) {
        started.fetch_add(1);
        const tessera_status s = tessera_execute(a, step, 0.0, &g, &f, 1);
        if (s == TESSERA_OK) continue;
        const std::string m = tessera_last_error(a);
        if (s != TESSERA_ERROR_CONFIG) ++bad;
        if (refused_or_closed(m)) return;  // the end of this adapter
        if (m.find("another thread is inside a call on this adapter") == std::string::npos) ++bad;
      }
    };
    std::thread t1(executor), t2(executor);
    wait_for(started, 4);
    std::atomic<int> closes_ok{0}, closes_refused{0};
    const auto closer = [&] {
      const tessera_status s = tessera_close(a);
      (s == TESSERA_OK ? closes_ok : closes_refused).fetch_add(1);
    };
    std::thread c1(closer), c2(closer);
    c1.join();
    c2.join();
    t1.join();
    t2.join();
    CHECK(bad == 0);
    CHECK(closes_ok == 1);
    CHECK(closes_refused == 1);
  }
}

TEST_CASE("close race: Adapter::close while another thread is inside execute waits for it",
          "[robustness][handles][race]") {
  TempDir dir;
  const std::string cfg = small_config(dir);
  const std::vector<float> v = to_float(blob_values(kN));
  const tessera_field f = dense_field("density", v.data(), kN);
  const tessera_grid g = unit_grid(kN);
  tessera::insitu::Adapter ad;
  for (int round = 0; round < kRounds; ++round) {
    REQUIRE(ad.open(cfg, -1) == TESSERA_OK);  // the same object, opened again
    std::atomic<int> started{0};
    tessera_status last = TESSERA_OK;
    std::string message;
    std::thread sim([&] {
      for (std::int64_t step = 0;; ++step) {
        started.fetch_add(1);
        last = ad.execute(step, 0.0, g, std::span<const tessera_field>(&f, 1), round % 2 == 1);
        if (last != TESSERA_OK) {
          message = ad.last_error();
          break;
        }
      }
    });
    wait_for(started, 2);
    CHECK(ad.close() == TESSERA_OK);
    sim.join();
    CHECK(last == TESSERA_ERROR_CONFIG);
    CHECK(refused_or_closed(message));
    CHECK_FALSE(ad.is_open());
  }
}

TEST_CASE("close race: closing twice from the only thread and last_error outlives the close",
          "[robustness][handles][race]") {
  TempDir dir;
  const std::string cfg = small_config(dir);
  tessera::insitu::Adapter ad;
  REQUIRE(ad.open(cfg, -1) == TESSERA_OK);
  CHECK(ad.close() == TESSERA_OK);
  CHECK(ad.close() == TESSERA_OK);
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  CHECK(tessera_field_unchanged(a, "density") == TESSERA_OK);
  CHECK(std::string(tessera_last_error(a)).empty());
  const char* before = tessera_last_error(a);
  CHECK(tessera_close(a) == TESSERA_OK);
  CHECK(std::string(before).empty());  // this thread's copy outlives the close
  CHECK(tessera_close(a) == TESSERA_ERROR_CONFIG);
}
