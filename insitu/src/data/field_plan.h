#pragma once
/// How this rank holds the field for one render, decided before anything is allocated:
/// replicated (a replica of the global field per node) or distributed (its own block plus a
/// bounded cache of other ranks' bricks), the cache's brick size and slots, and the check of
/// the render's estimated allocations against tessera.memory_limit_mb (docs/mpi.md,
/// "Distributed mode", and docs/insitu.md, "Limits and failure").
///
/// The rule for `distribution: auto`: replicated while this rank's share of its node's
/// replica (global field bytes / ranks on the node) is at most half of the memory limit;
/// otherwise distributed. Ranks may compute different answers (their nodes may differ), so
/// the caller combines them: distributed if any rank says so. One rank is always replicated.
#include "data/field_binding.h"

#include <tessera/brick_cache.h>
#include <tessera/config/config.h>
#include <tessera/memory_estimate.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace tessera::insitu {

/// The most the cache of a distributed render may hold by default (`tessera.brick_cache`):
/// 40% of the global field's bytes, so that a rank holds less than half of what a replica costs.
inline constexpr double kCacheFieldFraction = config::GlobalOptions::kDefaultBrickCache;

struct FieldPlan {
  bool distributed = false;                     ///< this rank's answer (combine across ranks for `auto`)
  int shift = 0;                                ///< distributed: bricks of 2^shift vertices per edge
  std::size_t capacity = 0;                     ///< distributed: cache slots
  std::uint64_t replica_share = 0;              ///< bytes of this rank's share of a node replica
  std::uint64_t limit = 0;                      ///< the memory limit in bytes
  double cache_fraction = kCacheFieldFraction;  ///< tessera.brick_cache: the cache's cap, of the field
  std::string limit_text;                       ///< how the limit was set, for messages
  MemoryEstimate base;                          ///< the render's own allocations without the field's
  int threads = 1;                              ///< rendering threads on this rank (paths in flight at once)
  int macrocell_edge = 8;                       ///< the scene's macrocell edge (level tables' size)
  bool gpu = false;                             ///< rendered on the GPU (its host bookkeeping counted)
  /// Distributed: a warning when the cache is too small for the bricks the paths in flight
  /// cross (small_cache_warning); "" otherwise.
  std::string cache_warning;
};

/// A cache of fewer than this many bricks per thread and per brick along the three axes
/// (capacity < kCacheSlotsPerCrossing x threads x (bricks along x + y + z)) cannot keep what
/// the rays being traced cross, so bricks are fetched again and again (measured: 5-40x the
/// replicated time, hundreds of times for a one-brick cache; docs/mpi.md): warned about.
inline constexpr std::int64_t kCacheSlotsPerCrossing = 4;

/// The warning for a distributed cache of `capacity` slots over `grid` with `threads`
/// rendering threads and `fraction` = tessera.brick_cache, or "" when the cache holds every
/// brick or at least kCacheSlotsPerCrossing x threads x (bricks along x + y + z).
std::string small_cache_warning(const BrickGrid& grid, std::size_t capacity, int threads, double fraction);

/// Bricks of 2^shift vertices per edge for a global grid: the power of two nearest below an
/// eighth of the longest axis, clamped to [8, 32] vertices. plan_distributed starts from it.
int brick_shift(const std::int64_t global_dims[3]);
inline constexpr int kMaxBrickShift = 5;  ///< bricks of at most 32^3 vertices

struct AmrLayout;  // amr_layout.h

/// The plan for `spec` on this rank (ranks: the communicator's size). Throws
/// std::runtime_error naming the estimate and the limit when even the chosen mode does not fit.
/// `amr`: the checked layout of a mesh with refinement levels (nullptr: a single level); the
/// estimate then counts this rank's share of the node's replica of every patch (several
/// ranks; one rank reads them in place) and the level tables (AmrLayout::table_bytes), and
/// `auto` decides on that replica share as for one level. `gpu`: the render runs on the CUDA
/// device (device_phase), so the estimate counts a call's host copies of its pixels.
FieldPlan plan_field(const config::Config& cfg, const config::RenderSpec& spec, const FieldBinding& binding, int ranks,
                     int ranks_on_node, bool root, const AmrLayout* amr = nullptr, bool gpu = false);

/// Sets plan.shift / capacity for distributed mode and checks the limit (throws like
/// plan_field); after the ranks have agreed on distributed for `auto`. The cache holds at most
/// tessera.brick_cache of the field's bytes (at least one brick; at 1, every brick) within
/// what the limit leaves. Bricks: brick_shift(), or the coarsest cut up to 32^3 of which the
/// cache can keep every brick (then nothing is evicted and fewer messages carry the field).
/// `shift` > 0 imposes the brick size instead (every rank must use the same cut: the caller
/// plans, takes the smallest shift over the ranks and plans again with it where it differs).
/// `amr` (refinement levels): the cache pages the levels' virtual grid
/// (AmrLayout::virtual_grid()) and its cap is taken of the patches' bytes; the level tables
/// are counted.
void plan_distributed(FieldPlan& plan, const FieldBinding& binding, int shift = 0, const AmrLayout* amr = nullptr);

/// One line for the log: the mode, and why (the rule's figures).
std::string describe_plan(const FieldPlan& plan, config::Distribution asked);

}  // namespace tessera::insitu
