#pragma once
/// How many worker threads one rank's render pass uses (rank_threads): the render itself (the
/// tile scheduler) and everything before it (prepare's passes over the field or mesh, the
/// adapter's checks, hashes and summaries), which run_render (pass/render_pass.cpp) runs
/// within that many threads (within_threads).
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <thread>
#include <utility>

namespace tessera::insitu {

/// `tessera.threads` when > 0. 0: the caller's arena's concurrency (all hardware threads
/// unless the simulation runs Tessera inside a narrower arena), divided among the ranks
/// sharing the node (`ranks_on_node` > 1) unless the launcher already bound this rank to
/// fewer cores than the machine has. Never more than TBB runs at once (global_control's
/// max_allowed_parallelism: more would only create idle arena slots), never below 1.
inline int rank_threads(int requested, int ranks_on_node) {
  int threads = requested;
  if (threads <= 0) {
    threads = tbb::this_task_arena::max_concurrency();
    if (ranks_on_node > 1 && threads >= static_cast<int>(std::thread::hardware_concurrency())) threads /= ranks_on_node;
  }
  const std::size_t cap = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return static_cast<int>(
      std::clamp<std::size_t>(static_cast<std::size_t>(std::max(1, threads)), 1, std::max<std::size_t>(1, cap)));
}

/// Runs `f` (returning its result) on at most `threads` threads: in the caller's arena when
/// that is exactly as wide, else inside a task_arena of that concurrency. Exceptions propagate.
template <class F>
decltype(auto) within_threads(int threads, F&& f) {
  if (threads == tbb::this_task_arena::max_concurrency()) return std::forward<F>(f)();
  tbb::task_arena arena(threads);
  return arena.execute(std::forward<F>(f));
}

}  // namespace tessera::insitu
