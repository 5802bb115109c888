#pragma once
/// Render statistics. Counters are integer sums, so they are identical for any thread count.
#include <cstdint>

namespace tessera {

struct RenderStats {
  std::uint64_t samples = 0;
  std::uint64_t free_flight_lookups = 0;    ///< field samples while sampling free paths
  std::uint64_t transmittance_lookups = 0;  ///< field samples for shadow / MIS rays
  std::uint64_t gradient_lookups = 0;       ///< field samples for gradients (shading)
  std::uint64_t real_collisions = 0;
  std::uint64_t null_collisions = 0;
  std::uint64_t discarded_samples = 0;      ///< NaN / Inf radiance samples dropped
  std::uint64_t nan_voxels_seen = 0;        ///< NaN vertices in the field (counted at prepare)
  std::uint64_t tiles_total = 0;
  std::uint64_t tiles_skipped = 0;          ///< tiles filled without tracing (culling)
  double wall_seconds = 0.0;                ///< rendering only
  int threads = 0;

  std::uint64_t density_lookups() const {
    return free_flight_lookups + transmittance_lookups + gradient_lookups;
  }
  void add_counters(const RenderStats& o);
};

}  // namespace tessera
