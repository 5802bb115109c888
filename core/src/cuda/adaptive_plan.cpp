/// The adaptive-sampling plan of a device call (adaptive_plan.h).
#include "cuda/adaptive_plan.h"

#include "kernel/adaptive_sampling.h"
#include "scene/prepared_scene_impl.h"

#include <algorithm>

namespace tessera::cuda {

namespace {
constexpr int B = kAdaptiveBlock;
static_assert(B * B <= 64, "a block's pixels are bits of one 64-bit mask");

/// A block's own pixels (bit j * B + i for pixel (i, j) of the block) and the culled ones.
struct BlockMarks {
  std::int64_t block;
  std::uint64_t own, culled;
};
}  // namespace

AdaptivePilot adaptive_pilot_jobs(const PreparedSceneImpl& s, std::span<const int> tile_indices) {
  const int width = s.kernel.width, height = s.kernel.height;
  const std::int64_t cols = adaptive_blocks(width);
  std::vector<BlockMarks> marks;
  for (const int ti : tile_indices) {
    const Tile& t = s.tiles[static_cast<std::size_t>(ti)];
    const bool culled = s.tile_culled[static_cast<std::size_t>(ti)] != 0;
    if (t.x1 <= t.x0 || t.y1 <= t.y0) continue;
    for (int by = t.y0 / B; by <= (t.y1 - 1) / B; ++by)
      for (int bx = t.x0 / B; bx <= (t.x1 - 1) / B; ++bx) {
        std::uint64_t m = 0;
        for (int y = std::max(t.y0, by * B); y < std::min(t.y1, by * B + B); ++y)
          for (int x = std::max(t.x0, bx * B); x < std::min(t.x1, bx * B + B); ++x)
            m |= std::uint64_t{1} << ((y - by * B) * B + (x - bx * B));
        marks.push_back({by * cols + bx, m, culled ? m : 0});
      }
  }
  std::sort(marks.begin(), marks.end(), [](const BlockMarks& a, const BlockMarks& b) { return a.block < b.block; });
  AdaptivePilot plan;
  for (std::size_t i = 0; i < marks.size();) {
    BlockMarks m = marks[i];
    for (++i; i < marks.size() && marks[i].block == m.block; ++i) {
      m.own |= marks[i].own;
      m.culled |= marks[i].culled;
    }
    const int x0 = static_cast<int>(m.block % cols) * B, y0 = static_cast<int>(m.block / cols) * B;
    const int bw = std::min(B, width - x0), bh = std::min(B, height - y0);
    plan.block_start.push_back(static_cast<std::int64_t>(plan.jobs.size()));
    for (int j = 0; j < bh; ++j)
      for (int k = 0; k < bw; ++k) {
        const std::uint64_t bit = std::uint64_t{1} << (j * B + k);
        const int kind = !(m.own & bit) ? kJobNeighbour : (m.culled & bit) ? kJobCulled : kJobTraced;
        plan.jobs.push_back({x0 + k, y0 + j, kind});
      }
  }
  plan.block_start.push_back(static_cast<std::int64_t>(plan.jobs.size()));
  return plan;
}

std::vector<int> adaptive_counts(std::span<const std::int64_t> block_start, std::span<const PixelJob> jobs,
                                 std::span<const PixelSums> sums, int pilot, int spp, double scale) {
  std::vector<int> n(jobs.size(), 0);
  for (std::size_t b = 0; b + 1 < block_start.size(); ++b) {
    const std::int64_t first = block_start[b], last = block_start[b + 1];
    for (std::int64_t p = first; p < last; ++p) {
      if (jobs[static_cast<std::size_t>(p)].culled == kJobNeighbour) continue;
      // The others' pilots pooled in the block's raster order, as sample_adaptive pools them
      PilotSums others;
      for (std::int64_t q = first; q < last; ++q) {
        if (q == p) continue;
        const PixelSums& o = sums[static_cast<std::size_t>(q)];
        others.add(PilotSums{o.lum, o.lum2, o.n});
      }
      n[static_cast<std::size_t>(p)] = adaptive_count(others, pilot, spp, scale);
    }
  }
  return n;
}

}  // namespace tessera::cuda
