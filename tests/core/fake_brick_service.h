#pragma once
/// A stand-in for the other ranks in distributed mode (brick_cache.h): one std::thread that
/// serves a BrickCache from a whole in-memory field, as the in situ service thread serves it
/// from MPI. Test code only.
#include <tessera/brick_cache.h>
#include <tessera/field_view.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

namespace tessera_test {

class FakeBrickService {
 public:
  /// Serves `cache` from `whole` (the global field, dense or not) until destroyed. After
  /// `fail_after` published bricks it calls cache.fail() instead (0: never).
  FakeBrickService(tessera::BrickCache& cache, const tessera::FieldView& whole, std::uint64_t fail_after = 0)
      : m_cache(cache), m_whole(whole), m_fail_after(fail_after), m_thread([this] { run(); }) {}
  ~FakeBrickService() {
    m_stop = true;
    m_thread.join();
  }
  FakeBrickService(const FakeBrickService&) = delete;
  FakeBrickService& operator=(const FakeBrickService&) = delete;

 private:
  void run() {
    std::vector<std::int64_t> pending;
    std::uint64_t served = 0;
    while (!m_stop.load()) {
      m_cache.take_wanted(pending, std::chrono::microseconds(2000));
      if (m_cache.failed()) {
        pending.clear();
        continue;
      }
      std::size_t i = 0;
      for (; i < pending.size(); ++i) {
        if (m_fail_after != 0 && served >= m_fail_after) {
          m_cache.fail("fake service: failing after " + std::to_string(served) + " bricks");
          break;
        }
        unsigned char* slot = m_cache.reserve(pending[i]);
        if (!slot) {
          if (!m_cache.try_flush()) break;  // wait in take_wanted until the flush can happen
          slot = m_cache.reserve(pending[i]);
        }
        fill(pending[i], slot);
        m_cache.publish(pending[i]);
        ++served;
      }
      pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }

  /// Copies brick b's vertices from the whole field into its slot (layout of brick_cache.h).
  void fill(std::int64_t b, unsigned char* slot) const {
    const tessera::BrickGrid& g = m_cache.grid();
    std::int64_t lo[3], hi[3];
    g.box(b, lo, hi);
    const std::size_t es = tessera::dtype_size(g.dtype);
    const std::int64_t B = g.edge();
    const auto* base = static_cast<const unsigned char*>(m_whole.data);
    for (std::int64_t k = lo[2]; k < hi[2]; ++k)
      for (std::int64_t j = lo[1]; j < hi[1]; ++j)
        for (std::int64_t i = lo[0]; i < hi[0]; ++i) {
          const std::int64_t e = ((k - lo[2]) * B + (j - lo[1])) * B + (i - lo[0]);
          std::memcpy(slot + static_cast<std::size_t>(e) * es,
                      base + i * m_whole.byte_strides[0] + j * m_whole.byte_strides[1] + k * m_whole.byte_strides[2],
                      es);
        }
  }

  tessera::BrickCache& m_cache;
  tessera::FieldView m_whole;
  std::uint64_t m_fail_after;
  std::atomic<bool> m_stop{false};
  std::thread m_thread;
};

}  // namespace tessera_test
