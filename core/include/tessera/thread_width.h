#pragma once
/// How wide a piece of parallel work may run: the cap TBB puts on every arena
/// (thread_cap) and a runner that keeps a callable to a given number of threads
/// (within_threads). Shared by the renderer (render_threads: options.threads) and the in
/// situ adapter (a rank's share of the node), so that both clamp and nest arenas alike.
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <utility>

namespace tessera {

/// The most threads TBB runs at once: global_control's max_allowed_parallelism (the hardware
/// threads unless the process lowered it), never below 1. An arena wider than this would only
/// hold idle slots.
inline int thread_cap() {
  const std::size_t cap = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return static_cast<int>(std::clamp<std::size_t>(cap, 1, 1u << 20));
}

/// `want` clamped to [1, thread_cap()]; want <= 0 means the current arena's concurrency.
inline int clamp_threads(int want) {
  if (want <= 0) want = tbb::this_task_arena::max_concurrency();
  return std::clamp(want, 1, thread_cap());
}

/// Runs `f` (returning its result) on at most clamp_threads(threads) threads: in the caller's
/// arena when that is exactly as wide, else inside a task_arena of that concurrency (nested
/// parallel algorithms inside `f` stay in it). Exceptions propagate.
template <class F>
decltype(auto) within_threads(int threads, F&& f) {
  threads = clamp_threads(threads);
  if (threads == tbb::this_task_arena::max_concurrency()) return std::forward<F>(f)();
  tbb::task_arena arena(threads);
  return arena.execute(std::forward<F>(f));
}

}  // namespace tessera
