#pragma once
/// How the tile and preview kernels (tile_kernel.h) are run on worker threads: how many
/// (render_threads, within_render_threads) and each work item's bracket on a paged field's
/// cache (TileBracket). Shared by the tile scheduler (render/render.cpp), prepare
/// (scene/prepare.cpp) and its adaptive preview (scene/adaptive_preview.cpp).
#include <tessera/brick_cache.h>
#include <tessera/render.h>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <utility>

namespace tessera {

/// Worker threads for a render: options.threads (0 = the current arena's concurrency), never
/// more than TBB will run at once (global_control max_allowed_parallelism, the hardware
/// threads unless the caller lowered it). Asking for more would only create idle arena slots.
inline int render_threads(const RenderOptions& o) {
  const int cap = static_cast<int>(
      std::max<std::size_t>(1, tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
  const int want = o.threads > 0 ? o.threads : tbb::this_task_arena::max_concurrency();
  return std::clamp(want, 1, cap);
}

/// Runs `f` (returning its result) with at most render_threads(o) threads: in the caller's
/// arena when that is exactly as wide, else inside a task_arena of that concurrency, so that
/// the parallel passes of prepare() (the field summary, the mesh check, sort and tables) keep
/// to options.threads as the render does. Exceptions propagate.
template <class F>
decltype(auto) within_render_threads(const RenderOptions& o, F&& f) {
  const int threads = render_threads(o);
  if (threads == tbb::this_task_arena::max_concurrency()) return std::forward<F>(f)();
  tbb::task_arena arena(threads);
  return arena.execute(std::forward<F>(f));
}

/// A work item's bracket for a paged field's cache (enter_tile / leave_tile, brick_cache.h):
/// lets the cache be emptied only while no worker is inside a tile. Nothing for a replicated
/// field (null cache).
class TileBracket {
 public:
  explicit TileBracket(BrickCache* cache) : m_cache(cache) {
    if (m_cache) m_cache->enter_tile();
  }
  ~TileBracket() {
    if (m_cache) m_cache->leave_tile();
  }
  TileBracket(const TileBracket&) = delete;
  TileBracket& operator=(const TileBracket&) = delete;

 private:
  BrickCache* m_cache;
};

}  // namespace tessera
