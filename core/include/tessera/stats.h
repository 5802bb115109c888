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
  std::uint64_t discarded_samples = 0;  ///< NaN / Inf radiance samples dropped
  /// Paths ended by a loop guard (docs/physics.md "Loop guards"): a tracking or march step
  /// that did not advance t, a traversal over its step budget, or a degenerate ray. Each
  /// contributes nothing from that point on. 0 for every scene prepare() accepts unless the
  /// arithmetic degenerates; a warning otherwise (render_warnings).
  std::uint64_t stalled_paths = 0;
  std::uint64_t nan_voxels_seen = 0;  ///< NaN vertices in the field (counted at prepare)
  std::uint64_t tiles_total = 0;
  std::uint64_t tiles_skipped = 0;  ///< tiles filled without tracing (culling)
  /// Bytes copied host -> device and device -> host for a render on a GPU (field copy, tables,
  /// film sums); 0 on the CPU, and no field bytes when the field was device memory read in place.
  std::uint64_t bytes_to_device = 0;
  std::uint64_t bytes_to_host = 0;
  double wall_seconds = 0.0;  ///< rendering only
  int threads = 0;            ///< worker threads actually used (arena concurrency)

  std::uint64_t density_lookups() const { return free_flight_lookups + transmittance_lookups + gradient_lookups; }
  /// Combines every integer counter of `o` into this one by its rule in kRenderCounters
  /// (summed, or the larger kept). wall_seconds and threads are left alone: how they combine
  /// depends on what is being combined (threads of one render vs ranks vs renders).
  void add_counters(const RenderStats& o);
};

/// One integer counter of RenderStats: its name (as `--stats` JSON and the docs spell it),
/// the field, and how two values combine.
struct RenderCounter {
  enum class Combine {
    Sum,  ///< counted events: tiles, threads, ranks and renders add up
    Max,  ///< a property of the field, the same wherever it is counted: the larger is kept
  };
  const char* name;
  std::uint64_t RenderStats::*field;
  Combine combine;
};

/// Every integer counter of RenderStats, in the order `--stats` writes them. Whatever sums,
/// flushes, reduces over MPI ranks or prints the counters loops over this table, so a new
/// counter is one field above plus one row here (stats.cpp asserts that no field is missing).
inline constexpr RenderCounter kRenderCounters[] = {
    {"samples", &RenderStats::samples, RenderCounter::Combine::Sum},
    {"free_flight_lookups", &RenderStats::free_flight_lookups, RenderCounter::Combine::Sum},
    {"transmittance_lookups", &RenderStats::transmittance_lookups, RenderCounter::Combine::Sum},
    {"gradient_lookups", &RenderStats::gradient_lookups, RenderCounter::Combine::Sum},
    {"real_collisions", &RenderStats::real_collisions, RenderCounter::Combine::Sum},
    {"null_collisions", &RenderStats::null_collisions, RenderCounter::Combine::Sum},
    {"nan_voxels_seen", &RenderStats::nan_voxels_seen, RenderCounter::Combine::Max},
    {"discarded_samples", &RenderStats::discarded_samples, RenderCounter::Combine::Sum},
    {"stalled_paths", &RenderStats::stalled_paths, RenderCounter::Combine::Sum},
    {"tiles_total", &RenderStats::tiles_total, RenderCounter::Combine::Sum},
    {"tiles_skipped", &RenderStats::tiles_skipped, RenderCounter::Combine::Sum},
    {"bytes_to_device", &RenderStats::bytes_to_device, RenderCounter::Combine::Sum},
    {"bytes_to_host", &RenderStats::bytes_to_host, RenderCounter::Combine::Sum},
};

/// Fraction of discarded (non-finite) samples above which render_warnings warns: 1e-3.
inline constexpr double kDiscardedWarnFraction = 1e-3;

/// Warnings about a finished render, one sentence each (no prefix, no newline), empty when
/// there is nothing to say: discarded_samples / samples above kDiscardedWarnFraction, and
/// stalled_paths > 0. A warning never fails a render; callers print or record them. With the
/// prepared scene at hand, render_warnings(prepared, stats) (scene_warnings.h) says more.
std::vector<std::string> render_warnings(const RenderStats& stats);

}  // namespace tessera
