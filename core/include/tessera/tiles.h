#pragma once
/// Cutting the image into tiles and ordering them.
#include <vector>

namespace tessera {

enum class TileOrder { RowMajor, Morton };

struct Tile {
  int x0, y0, x1, y1;  ///< pixel rectangle [x0, x1) x [y0, y1)
};

/// Tiles of edge `edge` pixels (edge 0: one tile per image row, i.e. scanline order), listed
/// row-major or along a Morton (Z-order) curve over tile coordinates. Edge < 0 throws.
std::vector<Tile> make_tiles(int width, int height, int edge, TileOrder order);

}  // namespace tessera
