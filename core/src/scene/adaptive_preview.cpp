/// prepare's adaptive preview: runs the preview kernel (tile_kernel.h) over block rows in a
/// task arena of options.threads, as the tile scheduler (render/render.cpp) runs the tile kernel over tiles.
#include "scene/adaptive_preview.h"

#include <tessera/render.h>

#include "kernel/adaptive_sampling.h"
#include "kernel/kernel_scene.h"
#include "kernel/stop_check.h"
#include "kernels/tile_kernel.h"
#include "kernels/workers.h"

#include <tbb/parallel_for.h>

#include <cstdint>
#include <vector>

namespace tessera {

double adaptive_preview_scale(const KernelScene& s, const RenderOptions& options) {
  if (!(s.target_error > 0.0)) return 0.0;
  const PreviewKernel preview_row = preview_kernel(s);
  const int rows = adaptive_blocks(s.height);
  const int cols = adaptive_blocks(s.width);
  std::vector<PilotSums> blocks(static_cast<std::size_t>(rows) * cols);
  StopCheck stop(options.deadline);
  within_render_threads(options, [&] {
    tbb::parallel_for(0, rows, [&](int by) {
      if (stop.stop()) return;
      TileBracket bracket(s.paged.cache);
      preview_row(s, by, &blocks[static_cast<std::size_t>(by) * cols], stop);
    });
  });
  if (stop.stopped()) throw DeadlineExceeded(0, s.tile_count);
  return preview_scale(blocks, cols, s.target_error);  // the same for any thread count
}

}  // namespace tessera
