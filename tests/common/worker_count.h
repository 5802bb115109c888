#pragma once
// Which threads join a task arena: a test runs work from an arena it made, observed, and
// counts the worker threads that joined it (none: the work ran in an arena of its own).
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <atomic>

namespace tessera_test {

/// Counts the worker threads that join one arena while it is observed.
class WorkerCount : public tbb::task_scheduler_observer {
 public:
  explicit WorkerCount(tbb::task_arena& arena) : tbb::task_scheduler_observer(arena) { observe(true); }
  ~WorkerCount() override { observe(false); }
  void on_scheduler_entry(bool is_worker) override {
    if (is_worker) m_entries.fetch_add(1, std::memory_order_relaxed);
  }
  int entries() const { return m_entries.load(std::memory_order_relaxed); }

 private:
  std::atomic<int> m_entries{0};
};

/// Worker threads of a fresh arena (as wide as the machine) that joined while `fn` ran in it.
template <class F>
int workers_joining(F&& fn) {
  tbb::task_arena arena;
  arena.initialize();
  WorkerCount count(arena);
  arena.execute(fn);
  return count.entries();
}

/// The control of a test that expects no worker to join: whether any joined `fn` in one of
/// `tries` runs. Workers join only once the OS schedules them while the work lasts, which a
/// loaded machine (a parallel ctest) may not do in time: false is then inconclusive, never a
/// failure of the code under test.
template <class F>
bool workers_can_join(F&& fn, int tries = 5) {
  for (int t = 0; t < tries; ++t)
    if (workers_joining(fn) > 0) return true;
  return false;
}

}  // namespace tessera_test
