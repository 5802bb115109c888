#pragma once
/// The checks every render_tiles entry makes of its arguments (the CPU's, and the GPU
/// backend's on any device).
#include <tessera/film.h>

#include <span>

namespace tessera {

struct PreparedSceneImpl;

/// Throws std::invalid_argument for a film whose size is not the scene's image, and
/// std::out_of_range for a tile index outside the scene's tiles, naming them.
void check_tiles_call(const PreparedSceneImpl& s, const Film& film, std::span<const int> tile_indices);

}  // namespace tessera
