#pragma once
/// KernelScene: everything the per-sample kernels read, as one trivially copyable struct of
/// plain values, pointers and views, filled by prepare() (make_kernel_scene). It owns nothing:
/// every pointer refers into the PreparedSceneImpl that made it (majorant table, transfer
/// functions, lights, environment, tiles) or to the caller's field, and is valid while that
/// prepared scene lives and the field's memory is unchanged. This is what a second backend (a
/// data-distributed or GPU renderer) is handed; read-only while rendering, so any number of
/// threads may share one.
#include <tessera/brick_cache.h>
#include <tessera/camera.h>
#include <tessera/field_view.h>
#include <tessera/integrator.h>
#include <tessera/tiles.h>
#include <tessera/transfer_function.h>

#include "kernel/amr_view.h"
#include "kernel/axis_map.h"
#include "kernel/magnitude_view.h"
#include "lights/light_set.h"
#include "mesh/mesh_field_view.h"

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace tessera {

struct KernelScene {
  // Image and random streams
  int width = 0, height = 0;    ///< pixels
  int spp = 0;                  ///< samples per pixel (the adaptive maximum)
  double target_error = 0.0;    ///< adaptive sampling's target; 0 = uniform sampling
  double adaptive_scale = 0.0;  ///< samples per unit of sigma (adaptive_sampling.h); 0 = off
  std::uint64_t seed = 0, frame = 0;
  Camera camera;

  // Medium: the field, its placement, its majorants and the transfer functions
  FieldView field;               ///< paged: the global dims and dtype, data null (never read)
  PagedFieldView paged;          ///< paged mode (brick_cache.h) when paged.cache is set
  AmrFieldView amr;              ///< refinement levels (amr_view.h) when amr.nlevels > 0
  MagnitudeFieldView magnitude;  ///< a vector's magnitude (magnitude_view.h) when active()
  MeshFieldView mesh;            ///< a curvilinear or unstructured mesh (mesh_field_view.h) when mesh.element is set
  const TransferFunction* tf = nullptr;
  /// The medium's p space (grid_medium.h): p = (x - origin) * inv_spacing per axis. Uniform
  /// axis: origin the world position of sample 0 (a vertex, or the first cell's centre),
  /// inv_spacing 1 / spacing; rectilinear axis: origin 0 and inv_spacing 1 (p = x).
  Vec3 origin{0.0};
  Vec3 inv_spacing{1.0};
  double box_lo[3] = {0.0, 0.0, 0.0};  ///< the medium's box in p (the cells' box for cell data)
  double box_hi[3] = {0.0, 0.0, 0.0};
  AxisMap axis[3];                            ///< per axis; coords == nullptr: uniform (axis_tables.h builds them)
  bool outer_half = false;                    ///< cell data: the outermost macrocells reach over the outer half cell
  const double* majorant = nullptr;           ///< per macrocell, 1 / world unit, x fastest
  const std::uint8_t* empty_reach = nullptr;  ///< per macrocell (field/empty_reach.h); null: no skipping
  std::int64_t cells[3] = {1, 1, 1};
  int cell_edge = 1;          ///< macrocell edge in voxels
  double max_majorant = 0.0;  ///< 0: the medium is empty for this TF
  double sigma_max = 0.0;     ///< extinction clamp, 1 / world unit (loop_bounds.h)
  double march_step = 0.5;    ///< raymarch step, world units

  // Integrator (each mode is read once per ray or collision where it acts, never per step)
  int max_depth = 1;  ///< real collisions per path (1 for single scattering)
  int rr_depth = 3;
  Shading shading = Shading::Hybrid;
  FreePath free_path = FreePath::Delta;
  ShadowMode shadow = ShadowMode::Ratio;
  bool shadow_roulette = true;
  SamplerKind sampler = SamplerKind::Sobol;
  double gradient_factor = 1.0;
  double phase_g = 0.0;
  bool has_emission = false;
  bool has_specular = false;

  LightSet lights;

  // Tiles: the scene's list and the culling verdict of each (1 = nothing to trace)
  const Tile* tiles = nullptr;
  const std::uint8_t* tile_culled = nullptr;
  std::size_t tile_count = 0;
};
static_assert(std::is_trivially_copyable_v<KernelScene>);

}  // namespace tessera
