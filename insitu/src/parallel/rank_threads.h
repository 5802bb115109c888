#pragma once
/// How many worker threads one rank's render pass uses (rank_threads): the render itself (the
/// tile scheduler) and everything before it (prepare's passes over the field or mesh, the
/// adapter's checks, hashes and summaries), which run_render (pass/render_pass.cpp) runs
/// within that many threads (within_threads).
#include <tessera/thread_width.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <thread>

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
  return clamp_threads(std::max(1, threads));
}

/// The runner itself is core's (tessera::within_threads, thread_width.h).
using tessera::within_threads;

}  // namespace tessera::insitu
