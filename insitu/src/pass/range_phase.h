#pragma once
/// The range phase: the field's global finite min/max, when the render's `when` trigger or
/// `range: auto` needs it; once per field and call (CallData::ranges), from a summary where
/// one is kept or made here, else one pass over this rank's blocks and a reduction. Before it,
/// the ranks agree whether the field summaries carried from the last call may be kept.
#include "pass/bind_phase.h"

#include <tessera/adapter.h>

#include <optional>
#include <utility>

namespace tessera::insitu {

/// Collective (one agreement, once per field and call): keeps the summaries the last call
/// left for `field` only if every rank may (marked unchanged, same layout), else drops them.
void agree_on_kept_summaries(const PassContext& pass, const BoundField& field);

/// The global finite range of `field` (lo > hi when no rank has a finite value). Counts a
/// pass over the values in result.field_passes. Nothing when the ranks agreed on a failure.
std::optional<std::pair<double, double>> range_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field,
                                                     RenderResult& result);

}  // namespace tessera::insitu
