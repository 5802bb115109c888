#pragma once
/// Where the render reads its field from, in two phases:
///   plan (memory and distribution): the render's own allocations estimated before any is
///     made (replica or brick cache, film, images, envmap), replicated or distributed decided
///     (`auto` on every rank, then agreed; one brick cut for all: the finest any rank chose);
///     after the `when` decision, so a render that does not fire is not refused;
///   assemble: the global field assembled once per consecutive use (zero copy on one rank),
///     or in distributed mode this rank's blocks and a cache for the other ranks' bricks
///     (with refinement levels: every rank's patches paged through one virtual grid).
#include "data/field_plan.h"
#include "pass/bind_phase.h"

#include <tessera/amr.h>
#include <tessera/brick_cache.h>

#include <cstdint>
#include <memory>
#include <optional>

namespace tessera::insitu {

/// The field as this render reads it.
struct PlacedField {
  FieldPlan plan;                   ///< replicated or distributed, and the cache's size
  PagedField paged;                 ///< distributed mode: this rank's blocks and the brick cache
  AmrVirtualLayout virtual_layout;  ///< distributed mode with levels: the virtual grid of the patches
  /// Distributed mode, one level: the global summary (kept, or reduced from every rank's
  /// blocks in a phase of its own, before the prepare that serves bricks)
  std::shared_ptr<const FieldSummary> summary;
  /// Replicated on the device (FieldDevice::assemble_on_device): the host blocks' bytes the
  /// assembly copied to the device; 0 when the call's replica was reused
  std::uint64_t assembled_to_device = 0;
};

/// The plan phase (rank 0 logs the mode when it changes, unless `quiet`). Nothing when the
/// ranks agreed on a failure.
std::optional<FieldPlan> plan_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field, bool quiet);

/// The assemble phase: replicated, the global field in pass.call (assembled, or
/// assembled_patches with levels, keyed by the field); distributed, the paged field.
/// Nothing when the ranks agreed on a failure.
std::optional<PlacedField> assemble_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field,
                                          FieldPlan plan);

}  // namespace tessera::insitu
