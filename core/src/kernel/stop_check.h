#pragma once
/// StopCheck: a render's deadline (RenderOptions::deadline), shared by every thread of one
/// render. Polled before each work item, before each pixel of a tile, every 64 samples of
/// one pixel and every kStopPollBounces collisions of one path: one relaxed load, plus a
/// clock read when a deadline is set. Never per sample or per tracking step. Once passed,
/// every later poll on every thread says stop. Thread-safe; allocates nothing.
#include <atomic>
#include <chrono>

namespace tessera {

class StopCheck {
 public:
  using Clock = std::chrono::steady_clock;

  explicit StopCheck(Clock::time_point deadline) : m_deadline(deadline) {}
  bool stop() {
    if (m_stopped.load(std::memory_order_relaxed)) return true;
    if (m_deadline == Clock::time_point::max() || Clock::now() < m_deadline) return false;
    m_stopped.store(true, std::memory_order_relaxed);
    return true;
  }
  bool stopped() const { return m_stopped.load(std::memory_order_relaxed); }

 private:
  Clock::time_point m_deadline;
  std::atomic<bool> m_stopped{false};
};

/// A path polls the deadline after every this many real collisions (a power of two): with
/// max_bounces up to 10^6 and a dense, white medium one path can otherwise outlast any limit.
inline constexpr int kStopPollBounces = 256;

}  // namespace tessera
