/// make_kernel_scene: the KernelScene (kernel/kernel_scene.h) of a prepared scene.
#include "scene/prepared_scene_impl.h"

namespace tessera {

KernelScene make_kernel_scene(const PreparedSceneImpl& p) {
  const SceneDesc& d = p.desc;
  KernelScene k;
  // Image and random streams
  k.width = d.image.width;
  k.height = d.image.height;
  k.spp = d.image.spp;
  k.target_error = d.image.target_error;
  k.seed = d.options.seed;
  k.frame = d.options.frame;
  k.camera = p.camera;
  // Medium
  k.field = p.field;
  k.mesh = p.mesh.view();
  k.tf = &d.tf;
  k.origin = p.origin;
  k.inv_spacing = p.inv_spacing;
  for (int a = 0; a < 3; ++a) {
    k.box_lo[a] = p.box_lo[a];
    k.box_hi[a] = p.box_hi[a];
    k.axis[a] = p.axes.map(a);
  }
  k.outer_half = d.geometry.association == Association::Cell;
  k.majorant = p.grid.majorants();
  k.empty_reach = p.grid.empty_reach();
  for (int a = 0; a < 3; ++a) k.cells[a] = p.grid.cells()[a];
  k.cell_edge = p.grid.edge();
  k.max_majorant = p.grid.max_majorant();
  k.sigma_max = p.sigma_max;
  k.march_step = p.march_step;
  // Integrator; single scattering is the path tracer with one real collision
  const IntegratorDesc& in = d.integrator;
  k.max_depth = in.scattering == Scattering::Single ? 1 : in.max_bounces;
  k.rr_depth = in.rr_depth;
  k.shading = in.shading;
  k.free_path = in.free_path;
  k.shadow = in.shadow;
  k.shadow_roulette = in.shadow_roulette;
  k.sampler = in.sampler;
  k.gradient_factor = in.gradient_factor;
  k.phase_g = in.phase_g;
  k.has_emission = p.has_emission;
  k.has_specular = p.has_specular;
  k.lights = LightSet(p.lights.data(), static_cast<int>(p.lights.size()), &p.env);
  // Tiles
  k.tiles = p.tiles.data();
  k.tile_culled = p.tile_culled.data();
  k.tile_count = p.tiles.size();
  return k;
}

}  // namespace tessera
