#include <tessera/stats.h>

namespace tessera {

void RenderStats::add_counters(const RenderStats& o) {
  samples += o.samples;
  free_flight_lookups += o.free_flight_lookups;
  transmittance_lookups += o.transmittance_lookups;
  gradient_lookups += o.gradient_lookups;
  real_collisions += o.real_collisions;
  null_collisions += o.null_collisions;
  discarded_samples += o.discarded_samples;
  tiles_skipped += o.tiles_skipped;
}

}  // namespace tessera
