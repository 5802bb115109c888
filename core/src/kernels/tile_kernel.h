#pragma once
/// The per-tile kernel entry: what one worker runs for one tile (or band of rows of one),
/// chosen once per frame for the field's Value (with_value, kernel_dispatch.h). The
/// scheduler (render.cpp) decides which tiles run where; the kernel reads only the
/// KernelScene. Neither allocates, throws, logs nor locks; both are thread-safe across
/// distinct tiles (each pixel is written by the one call that owns it).
#include <tessera/film.h>
#include <tessera/stats.h>
#include <tessera/tiles.h>

#include "kernel/adaptive_sampling.h"
#include "kernel/kernel_scene.h"
#include "kernel/stop_check.h"

#include <cstdint>

namespace tessera {

/// Renders all samples of the pixels of `rect` (a tile, or a band of one) into the film,
/// adding its counters to `st`. `culled`: the tile's culling verdict. Stops early, leaving
/// the tile incomplete, once `stop` says so.
using TileKernel = void (*)(const KernelScene& ks, const Tile& rect, bool culled, Film& film, RenderStats& st,
                            StopCheck& stop);
TileKernel tile_kernel(const KernelScene& ks);

/// The adaptive-sampling preview (adaptive_sampling.h) of block row `by`: per block, the
/// pilot samples of its middle pixel (preview_pixel) into row[bx], for every block of the row.
/// Stops early, leaving later blocks empty, once `stop` says so.
using PreviewKernel = void (*)(const KernelScene& ks, int by, PilotSums* row, StopCheck& stop);
PreviewKernel preview_kernel(const KernelScene& ks);

}  // namespace tessera
