#pragma once
/// What prepare() derives from a SceneDesc and a field; read-only while rendering.
#include <tessera/camera.h>
#include <tessera/render.h>

#include "area_lights.h"
#include "environment.h"
#include "majorant_grid.h"

#include <vector>

namespace tessera {

inline constexpr int kMaxLights = 64;

struct PreparedSceneImpl {
  SceneDesc desc;
  FieldView field;
  Bounds bounds;
  Camera camera;
  MajorantGrid grid;
  Environment env;
  std::vector<RectLight> rects;
  std::vector<SphereLight> spheres;
  std::vector<Tile> tiles;
  std::vector<std::uint8_t> tile_culled;  ///< per tile: 1 = nothing to trace (tile_culling.h)
  Vec3 inv_spacing{1.0};
  double march_step = 0.5;   ///< raymarch step in world units
  double sigma_max = 0.0;    ///< extinction clamp, 1 / world unit (loop_bounds.h)
  bool has_emission = false;
  bool has_specular = false;
  int light_count = 0;       ///< rects + spheres + (background if it emits)
  double adaptive_scale = 0.0;  ///< samples per unit of sigma (adaptive_sampling.h); 0 = off
  bool summary_reused = false;  ///< the grid's FieldSummary came from the caller
};

}  // namespace tessera
