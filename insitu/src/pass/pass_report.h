#pragma once
/// What a render reports: its outcome started (name, step, plan), a render the budget
/// skipped (a warning naming the budget, logged the 1st, 2nd, 4th, 8th, ... time in a row),
/// and a finished render's figures, log line and warnings about the image.
#include "data/field_plan.h"
#include "pass/pass_context.h"

#include <tessera/render.h>

#include <cstddef>

namespace tessera::insitu {

/// The outcome of a render that fires, before any phase: its name, step, time, plan, budget.
PassOutcome begin_outcome(const PassContext& pass);

/// A render the budget skipped: no work, no files; rank 0's result carries the warning.
PassOutcome skipped(const PassContext& pass, PassOutcome out);

/// A render that finished: samples per second, samples per pixel over its `views` Cinema
/// views and its own camera, its cost against the simulation's time; rank 0 logs the
/// summary line (unless `quiet`) and the warnings about the image (never a failure).
void finish(const PassContext& pass, const PreparedScene& prepared, const FieldPlan& plan, std::size_t views,
            bool quiet, PassOutcome& out);

}  // namespace tessera::insitu
