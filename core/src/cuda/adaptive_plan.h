#pragma once
/// Adaptive sampling on the device (kernel/adaptive_sampling.h's contract, as the CPU's
/// sample_adaptive in kernels/tile_kernel_impl.h runs it): the host's plan of a call's two
/// passes. First every pixel of every 8x8 block the call's tiles touch draws its pilot
/// samples, the block's pixels outside the tiles too (neighbours: traced for the decision,
/// their samples not counted and not kept); then each of the tiles' pixels draws the rest of
/// its count, decided from the pilot sums of the other pixels of its block, pooled in the
/// CPU's order. Host code; the passes run on any DeviceBackend (device_render.cpp).
#include <tessera/film.h>

#include "kernels/slice_args.h"

#include <cstdint>
#include <span>
#include <vector>

namespace tessera {
struct PreparedSceneImpl;
}

namespace tessera::cuda {

/// The pilot pass's pixels, block by block (blocks in raster order of the image), each block's
/// pixels in raster order; own pixels keep their tile's culling (kJobTraced, kJobCulled),
/// the others are kJobNeighbour.
struct AdaptivePilot {
  std::vector<PixelJob> jobs;
  std::vector<std::int64_t> block_start;  ///< block b's jobs: [block_start[b], block_start[b + 1])
};

/// The blocks the listed tiles touch (tiles of `s`, valid indices) and their pixels.
/// O(pixels of the tiles + blocks log blocks) time, memory linear in the blocks' pixels.
AdaptivePilot adaptive_pilot_jobs(const PreparedSceneImpl& s, std::span<const int> tile_indices);

/// Each pilot job's total sample count: adaptive_count (adaptive_sampling.h) of the pilot sums
/// of the other pixels of its block (`sums`: one per pilot job, its pilot samples only, added
/// in index order), 0 for neighbours. `block_start` and `jobs` as an AdaptivePilot's; `pilot`,
/// `spp` and `scale` the scene's (adaptive_pilot(spp), KernelScene::adaptive_scale).
std::vector<int> adaptive_counts(std::span<const std::int64_t> block_start, std::span<const PixelJob> jobs,
                                 std::span<const PixelSums> sums, int pilot, int spp, double scale);

}  // namespace tessera::cuda
