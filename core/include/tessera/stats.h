#pragma once
/// Render statistics. Counters are integer sums, so they are identical for any thread count.
#include <cstdint>
#include <string>
#include <vector>

namespace tessera {

struct RenderStats {
  std::uint64_t samples = 0;
  std::uint64_t free_flight_lookups = 0;    ///< field samples while sampling free paths
  std::uint64_t transmittance_lookups = 0;  ///< field samples for shadow / MIS rays
  std::uint64_t gradient_lookups = 0;       ///< field samples for gradients (shading)
  std::uint64_t real_collisions = 0;
  std::uint64_t null_collisions = 0;
  std::uint64_t discarded_samples = 0;      ///< NaN / Inf radiance samples dropped
  /// Paths ended by a loop guard (docs/physics.md "Loop guards"): a tracking or march step
  /// that did not advance t, a traversal over its step budget, or a degenerate ray. Each
  /// contributes nothing from that point on. 0 for every scene prepare() accepts unless the
  /// arithmetic degenerates; a warning otherwise (render_warnings).
  std::uint64_t stalled_paths = 0;
  std::uint64_t nan_voxels_seen = 0;        ///< NaN vertices in the field (counted at prepare)
  std::uint64_t tiles_total = 0;
  std::uint64_t tiles_skipped = 0;          ///< tiles filled without tracing (culling)
  double wall_seconds = 0.0;                ///< rendering only
  int threads = 0;                          ///< worker threads actually used (arena concurrency)

  std::uint64_t density_lookups() const {
    return free_flight_lookups + transmittance_lookups + gradient_lookups;
  }
  void add_counters(const RenderStats& o);
};

/// Fraction of discarded (non-finite) samples above which render_warnings warns: 1e-3.
inline constexpr double kDiscardedWarnFraction = 1e-3;

/// Warnings about a finished render, one sentence each (no prefix, no newline), empty when
/// there is nothing to say: discarded_samples / samples above kDiscardedWarnFraction, and
/// stalled_paths > 0. A warning never fails a render; callers print or record them. With the
/// prepared scene at hand, render_warnings(prepared, stats) (scene_warnings.h) says more.
std::vector<std::string> render_warnings(const RenderStats& stats);

}  // namespace tessera
