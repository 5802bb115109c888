#pragma once
/// Integrator options (docs/physics.md "The estimator").
#include <cstdint>

namespace tessera {

enum class Scattering { Single, Multiple };
enum class Shading { Phase, Brdf, Hybrid };
enum class FreePath { Delta, Raymarch };
enum class MajorantMode { Grid, Global };
enum class ShadowMode { Ratio, Delta };
/// Where a sample's first dimensions (pixel, lens, the first collision's light and direction
/// samples) come from: the path's own random stream, or a scrambled Sobol' sequence per pixel.
enum class SamplerKind { Independent, Sobol };

struct IntegratorDesc {
  Scattering scattering = Scattering::Single;
  int max_bounces = 16;  ///< multiple: real collisions per path, >= 1
  int rr_depth = 3;      ///< multiple: Russian roulette from this collision on
  Shading shading = Shading::Hybrid;
  double gradient_factor = 1.0;  ///< hybrid: P_brdf = 1 - exp(-gradient_factor * |grad u|_voxel)
  double phase_g = 0.0;          ///< Henyey-Greenstein g in (-1, 1)
  FreePath free_path = FreePath::Delta;
  MajorantMode majorant = MajorantMode::Grid;
  int macrocell = 8;  ///< macrocell edge in voxels (grid majorant)
  double step = 0.5;  ///< raymarch step, in voxels (of the smallest spacing)
  ShadowMode shadow = ShadowMode::Ratio;
  bool shadow_roulette = true;               ///< Russian roulette on ratio-tracking throughput < 0.1
  bool culling = true;                       ///< fill tiles that see only the background without tracing
  SamplerKind sampler = SamplerKind::Sobol;  ///< low-discrepancy first dimensions (sobol_sampler.h)
};

}  // namespace tessera
