#pragma once
/// How the tile and preview kernels (tile_kernel.h) are run on worker threads: how many
/// (render_threads, within_render_threads) and each work item's bracket on a paged field's
/// cache (TileBracket). Shared by the tile scheduler (render/render.cpp), prepare
/// (scene/prepare.cpp) and its adaptive preview (scene/adaptive_preview.cpp).
#include <tessera/brick_cache.h>
#include <tessera/render.h>
#include <tessera/thread_width.h>

#include <utility>

namespace tessera {

/// Worker threads for a render: options.threads (0 = the current arena's concurrency), never
/// more than TBB will run at once (thread_cap, thread_width.h).
inline int render_threads(const RenderOptions& o) { return clamp_threads(o.threads); }

/// Runs `f` (returning its result) with at most render_threads(o) threads (within_threads,
/// thread_width.h), so that the parallel passes of prepare() (the field summary, the mesh
/// check, sort and tables) keep to options.threads as the render does. Exceptions propagate.
template <class F>
decltype(auto) within_render_threads(const RenderOptions& o, F&& f) {
  return within_threads(o.threads, std::forward<F>(f));
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
