// `integrator:`: estimator choices (core IntegratorDesc) plus seed and tiling.
#include <tessera/config/render_spec.h>

#include "enum_names.h"
#include "parsers.h"

#include <limits>

namespace tessera::config::detail {

IntegratorSpec parse_integrator(const Value& v) {
  const Map m = v.map_with_keys({"scattering", "max_bounces", "rr_depth", "shading", "gradient_factor", "phase_g",
                                 "free_path", "majorant", "macrocell", "step", "shadow", "shadow_roulette", "culling",
                                 "sampler", "seed", "tile", "tile_order"});
  IntegratorSpec s;
  IntegratorDesc& d = s.desc;
  d.scattering = m.choice_or("scattering", d.scattering, kScatteringNames);
  d.max_bounces = static_cast<int>(m.integer_or("max_bounces", d.max_bounces, 1, 1000000));
  d.rr_depth = static_cast<int>(m.integer_or("rr_depth", d.rr_depth, 1, 1000000));
  d.shading = m.choice_or("shading", d.shading, kShadingNames);
  d.gradient_factor = m.number_or("gradient_factor", d.gradient_factor, Range::at_least(0.0));
  d.phase_g = m.number_or("phase_g", d.phase_g, Range::open(-1.0, 1.0));
  d.free_path = m.choice_or("free_path", d.free_path, kFreePathNames);
  d.majorant = m.choice_or("majorant", d.majorant, kMajorantNames);
  d.macrocell = static_cast<int>(m.integer_or("macrocell", d.macrocell, 1, 256));
  d.step = m.number_or("step", d.step, Range::above(0.0));
  d.shadow = m.choice_or("shadow", d.shadow, kShadowNames);
  d.shadow_roulette = m.boolean_or("shadow_roulette", d.shadow_roulette);
  d.culling = m.boolean_or("culling", d.culling);
  d.sampler = m.choice_or("sampler", d.sampler, kSamplerNames);
  if (const auto seed = m.get("seed")) s.seed = seed->unsigned64();
  s.tile = static_cast<int>(m.integer_or("tile", s.tile, 0, 16384));
  s.tile_order = m.choice_or("tile_order", s.tile_order, kTileOrderNames);
  return s;
}

}  // namespace tessera::config::detail
