// One render of one execute call, as the list of its phases (render_pass.h).
#include "pass/render_pass.h"

#include "parallel/rank_threads.h"
#include "pass/bind_phase.h"
#include "pass/cinema_phase.h"
#include "pass/device_phase.h"
#include "pass/mesh_pass.h"
#include "pass/pass_context.h"
#include "pass/pass_report.h"
#include "pass/placement_phase.h"
#include "pass/prepare_phase.h"
#include "pass/range_phase.h"
#include "pass/render_phase.h"
#include "pass/write_phase.h"

#include <exception>
#include <optional>
#include <utility>

namespace tessera::insitu {
namespace {

/// The render in its call: its samples per pixel (the budget's plan) and its deadline
/// (tessera.time_limit: one for the whole render, every Cinema view included).
PassContext pass_context(ParallelContext& ctx, const config::Config& cfg, RenderState& render, CallData& call,
                         SummaryCache& summaries) {
  const config::RenderSpec& spec = *render.spec;
  const PassClock::time_point start = PassClock::now();
  PassClock::time_point deadline = PassClock::time_point::max();
  if (cfg.global.time_limit > 0.0)
    deadline =
        start + std::chrono::duration_cast<PassClock::duration>(std::chrono::duration<double>(cfg.global.time_limit));
  return PassContext{ctx,    cfg,      spec,
                     render, call,     summaries,
                     start,  deadline, planned_spp(call.budget_plan, BudgetLimits{spec.image.spp, spec.min_spp})};
}

/// The phases, in order; each returns nothing (or false) when the ranks agreed on a failure,
/// which `out` then holds. check_when: the render fires only if its `when` trigger does.
PassOutcome run(const PassContext& pass, bool check_when, bool quiet) {
  PassOutcome out = begin_outcome(pass);
  PhaseGate gate(pass, out);
  // The render budget cannot give this render min_spp: skipped before any work (a `when`
  // render once its trigger has fired)
  if (pass.spp == 0 && !check_when) return skipped(pass, std::move(out));
  if (pass.call.pub.mesh_call) {
    run_mesh(pass, gate, out, check_when, quiet);
    return out;
  }

  std::optional<BoundField> field = bind_phase(gate, pass);
  if (!field || !device_phase(gate, pass, *field)) return out;
  out.result.device = config::device_text(field->device.selection);
  out.result.stats.bytes_to_host += field->device.staging.bytes;
  agree_on_kept_summaries(pass, *field);
  std::pair<double, double> range{0.0, 0.0};  // only when the trigger or `range: auto` needs it
  if (check_when || pass.spec.transfer_function.range.automatic) {
    const std::optional<std::pair<double, double>> r = range_phase(gate, pass, *field, out.result);
    if (!r) return out;
    if (check_when && !pass.render.trigger.fires_on_max(r->second)) {
      out.fired = false;
      return out;
    }
    if (r->first <= r->second) range = *r;  // else no finite value anywhere: (0, 0)
  }
  if (pass.spp == 0) return skipped(pass, std::move(out));

  std::optional<FieldPlan> plan = plan_phase(gate, pass, *field, quiet);
  if (!plan) return out;
  if (!plan->distributed && !stage_deferred(gate, pass, *field, out.result)) return out;
  std::optional<PlacedField> placed = assemble_phase(gate, pass, *field, std::move(*plan));
  if (!placed) return out;
  out.result.stats.bytes_to_device += placed->assembled_to_device;
  const std::optional<SceneSetup> setup = scene_phase(gate, pass, *field, range);
  if (!setup) return out;
  const std::optional<PreparedScene> prepared = prepare_phase(gate, pass, *field, *placed, setup->scene, out.result);
  if (!prepared) return out;
  std::optional<Image> img = render_phase(gate, pass, *prepared, out.result);
  if (!img || !write_phase(gate, pass, setup->scene, std::move(*img), out.result)) return out;
  if (pass.spec.output.cinema && !cinema_phase(gate, pass, *field, *placed, *setup, out.result)) return out;
  if (placed->plan.distributed) out.result.stats.bytes_to_host += pass.ctx.paged_bytes_from_device();
  finish(pass, *prepared, placed->plan, setup->views.size(), quiet, out);
  return out;
}

}  // namespace

PassOutcome run_render(ParallelContext& ctx, const config::Config& cfg, RenderState& render, CallData& call,
                       SummaryCache& summaries, bool check_when, bool quiet) noexcept {
  // Only agree() itself (e.g. a broken communicator) or memory exhaustion gets here
  PassOutcome out;
  out.fired = true;
  out.report_here = true;
  out.result.status = TESSERA_ERROR_RENDER;
  out.result.step = call.step;
  out.result.time = call.time;
  try {
    try {
      // Everything the pass runs over threads (prepare's passes, the adapter's checks, hashes
      // and summaries, the render) keeps to tessera.threads (rank_threads)
      return within_threads(rank_threads(cfg.global.threads, ctx.ranks_on_node()),
                            [&] { return run(pass_context(ctx, cfg, render, call, summaries), check_when, quiet); });
    } catch (const std::exception& e) {
      out.result.name = render.spec->name;
      out.result.error = "render '" + render.spec->name + "' at step " + std::to_string(call.step) + ": " + e.what();
    }
  } catch (...) {
    // No memory left even for the message: the status alone tells
  }
  return out;
}

}  // namespace tessera::insitu
