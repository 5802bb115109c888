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
  const int rows = (s.height + kAdaptiveBlock - 1) / kAdaptiveBlock;
  const int cols = (s.width + kAdaptiveBlock - 1) / kAdaptiveBlock;
  std::vector<double> sigma(rows, 0.0), lum(rows, 0.0);
  std::vector<std::uint64_t> count(rows, 0);
  StopCheck stop(options.deadline);
  within_render_threads(options, [&] {
    tbb::parallel_for(0, rows, [&](int by) {
      if (stop.stop()) return;
      TileBracket bracket(s.paged.cache);
      preview_row(s, by, &sigma[by], &lum[by], &count[by], stop);
    });
  });
  if (stop.stopped()) throw DeadlineExceeded(0, s.tile_count);
  // Row sums added in row order: the same for any thread count.
  double sigma_sum = 0.0, lum_sum = 0.0;
  std::uint64_t n = 0;
  for (int r = 0; r < rows; ++r) sigma_sum += sigma[r], lum_sum += lum[r], n += count[r];
  if (n == 0 || !(lum_sum > 0.0)) return 0.0;  // a black image: every pixel takes the pilot
  const double S_mean = sigma_sum / (static_cast<double>(rows) * cols);
  const double M = lum_sum / static_cast<double>(n);
  const double t = s.target_error;
  return S_mean / (t * t * M * M);
}

}  // namespace tessera
