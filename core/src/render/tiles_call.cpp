/// check_tiles_call (tiles_call.h).
#include "render/tiles_call.h"

#include "scene/prepared_scene_impl.h"

#include <stdexcept>
#include <string>

namespace tessera {

void check_tiles_call(const PreparedSceneImpl& s, const Film& film, std::span<const int> tile_indices) {
  if (film.width() != s.desc.image.width || film.height() != s.desc.image.height)
    throw std::invalid_argument("film is " + std::to_string(film.width()) + "x" + std::to_string(film.height()) +
                                ", scene image is " + std::to_string(s.desc.image.width) + "x" +
                                std::to_string(s.desc.image.height));
  const int ntiles = static_cast<int>(s.tiles.size());
  for (int i : tile_indices)
    if (i < 0 || i >= ntiles) throw std::out_of_range("tile index " + std::to_string(i) + " out of range");
}

}  // namespace tessera
