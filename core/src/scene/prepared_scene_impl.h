#pragma once
/// What prepare() derives from a SceneDesc and a field, and owns: read-only while rendering.
/// The kernels read none of it directly but the KernelScene `kernel`, which points into it.
#include <tessera/camera.h>
#include <tessera/render.h>

#include "field/majorant_grid.h"
#include "kernel/kernel_scene.h"
#include "lights/environment.h"
#include "lights/light_set.h"
#include "mesh/mesh_tables.h"
#include "scene/amr_tables.h"
#include "scene/axis_tables.h"

#include <memory>
#include <vector>

namespace tessera {

struct PreparedSceneImpl {
  SceneDesc desc;
  FieldView field;
  Bounds bounds;
  Camera camera;
  MajorantGrid grid;
  Environment env;
  std::vector<Light> lights;  ///< every light, in LightSet order (light_set.h)
  std::vector<Tile> tiles;
  std::vector<std::uint8_t> tile_culled;  ///< per tile: 1 = nothing to trace (tile_culling.h)
  /// The medium's p space and box (kernel_scene.h), and the rectilinear axes' tables
  Vec3 origin{0.0};
  Vec3 inv_spacing{1.0};
  double box_lo[3] = {0.0, 0.0, 0.0};
  double box_hi[3] = {0.0, 0.0, 0.0};
  AxisTables axes;
  AmrTables amr;            ///< refinement levels' lookup tables (empty for other fields)
  MeshTables mesh;          ///< a mesh's elements and location cells (empty for other fields)
  double march_step = 0.5;  ///< raymarch step in world units
  double sigma_max = 0.0;   ///< extinction clamp, 1 / world unit (loop_bounds.h)
  bool has_emission = false;
  bool has_specular = false;
  bool summary_reused = false;  ///< the grid's FieldSummary came from the caller
  /// Adaptive sampling on the GPU (options.device Cuda): the preview's scale is not made by
  /// prepare (kernel.adaptive_scale stays 0) but by every render call on the device, which
  /// reads the field where it lives (a device array the host cannot read); the same samples,
  /// hence the host's scale to rounding (cuda/device_render.cpp)
  bool preview_on_device = false;
  /// The kernels' view of all of the above (kernel_scene.h), made last by prepare().
  KernelScene kernel;
  /// A paged field's own block in GPU memory (PagedField::local_device), or null.
  const void* paged_local_device = nullptr;
  /// A paged field whose own block is device memory only (PagedField::local_device_only): the
  /// block as the device reads it (data: its device address) and its global vertex range; the
  /// host view (`kernel`) has no own block then. dims 0: none.
  FieldView paged_device_own;
  std::int64_t paged_device_lo[3] = {0, 0, 0};
  /// The CUDA backend's device copies of what `kernel` points to (cuda/device_scene.h), made
  /// by the first render_tiles_cuda and freed (cudaFree) with this object; null until then and
  /// in a CPU build. Guarded by render_cuda.cpp's lock.
  mutable std::shared_ptr<void> device_cache;
};

/// What `scene` holds (render.cpp and the core tests; not part of the public API).
const PreparedSceneImpl& prepared_scene_impl(const PreparedScene& scene);

/// The kernel scene of a prepared scene whose every other member is set; points into `p`
/// (make_kernel_scene.cpp).
KernelScene make_kernel_scene(const PreparedSceneImpl& p);

}  // namespace tessera
