#pragma once
/// Image-space culling: which tiles no camera ray can take to the medium or to a light.
/// Such tiles are filled with the background without tracing; the values are bit-identical to
/// tracing them, since a ray that meets nothing returns exactly the background.
#include "scene/prepared_scene_impl.h"

#include <cstdint>
#include <vector>

namespace tessera {

/// One flag per tile of p.tiles (1 = culled). Conservative: projects the bounding boxes of the
/// medium (when its majorant is not zero everywhere) and of every light; any box reaching
/// behind the camera, or a thin-lens camera, disables culling.
std::vector<std::uint8_t> cull_tiles(const PreparedSceneImpl& p);

}  // namespace tessera
