#pragma once
// Which threads join a task arena: a test runs work from an observed arena and counts the
// worker threads that joined it meanwhile (none: the work ran in an arena of its own).
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

/// An arena as wide as the machine, observed for the life of the process: made once and never
/// destroyed. (An observer switched off and destroyed with its arena after workers had joined
/// left TBB's proxy of it unreachable: a leak LeakSanitizer reports.)
struct ObservedArena {
  tbb::task_arena arena;
  WorkerCount count;
  ObservedArena() : count((arena.initialize(), arena)) {}
};

inline ObservedArena& observed_arena() {
  static ObservedArena* const probe = new ObservedArena();  // reachable to the end: not a leak
  return *probe;
}

/// Worker threads that joined the observed arena while `fn` ran in it.
template <class F>
int workers_joining(F&& fn) {
  ObservedArena& p = observed_arena();
  const int before = p.count.entries();
  p.arena.execute(fn);
  return p.count.entries() - before;
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
