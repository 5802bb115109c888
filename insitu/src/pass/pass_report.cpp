// What a render reports (pass_report.h).
#include "pass/pass_report.h"

#include "budget/render_budget.h"
#include "outputs/error_policy.h"

#include <tessera/scene_warnings.h>

#include <cstdio>
#include <string>
#include <utility>

namespace tessera::insitu {
namespace {

std::string summary(const PassContext& pass, const RenderResult& r) {
  const config::RenderSpec& spec = pass.spec;
  const RenderBudget* budget = pass.call.budget;
  char buf[256];
  std::snprintf(buf, sizeof buf, "render '%s' step %lld (t=%g): %dx%d, %d spp, %.3f s, %.3g samples/s", r.name.c_str(),
                static_cast<long long>(r.step), r.time, spec.image.width, spec.image.height, pass.spp, r.render_seconds,
                r.samples_per_second);
  std::string line = buf;
  // The render budget: the plan, what a pixel got, the account the plan had to spend
  if (budget) {
    std::snprintf(
        buf, sizeof buf,
        " (budget %g: %d of %d spp planned, %.3g a pixel on average, %.3g s in the account, the run at %.3gx so far)",
        pass.cfg.global.budget, pass.spp, spec.image.spp, r.actual_spp, budget->allowance(), budget->ratio());
    line += buf;
  }
  // The GPU: which, and the bytes copied between host and device (0 for a field read in place)
  if (r.device != "cpu") {
    std::snprintf(buf, sizeof buf, ", on %s, %llu bytes to the device, %llu to the host", r.device.c_str(),
                  static_cast<unsigned long long>(r.stats.bytes_to_device),
                  static_cast<unsigned long long>(r.stats.bytes_to_host));
    line += buf;
  } else if (r.stats.bytes_to_host > 0) {
    std::snprintf(buf, sizeof buf, ", on the CPU, %llu bytes of device arrays copied to the host",
                  static_cast<unsigned long long>(r.stats.bytes_to_host));
    line += buf;
  }
  if (spec.image.denoise) {
    std::snprintf(buf, sizeof buf, ", denoised in %.3f s", r.denoise_seconds);
    line += buf;
  }
  // The in situ cost: this render against the simulation's time it watched
  if (r.simulation_seconds > 0.0) {
    std::snprintf(buf, sizeof buf, ", %.3gx the simulation's %.3g s since the last render", r.cost_ratio,
                  r.simulation_seconds);
    line += buf;
  }
  if (spec.output.cinema) line += ", " + std::to_string(r.files.size()) + " files";
  else
    for (std::size_t i = 0; i < r.files.size(); ++i) line += (i ? ", " : " -> ") + r.files[i];
  return line;
}

}  // namespace

PassOutcome begin_outcome(const PassContext& pass) {
  PassOutcome out;
  out.fired = true;
  out.result.name = pass.spec.name;
  out.result.step = pass.call.step;
  out.result.time = pass.call.time;
  out.result.planned_spp = pass.spp;
  out.result.budget = pass.cfg.global.budget;
  return out;
}

PassOutcome skipped(const PassContext& pass, PassOutcome out) {
  RenderResult& r = out.result;
  r.budget_skipped = true;
  r.simulation_seconds = pass.call.simulation_seconds;
  const int n = ++pass.render.budget_skips;
  if (!pass.root()) return out;
  const RenderBudget* budget = pass.call.budget;
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "skipped: the render budget (tessera.budget = %g, rendering at most %gx the simulation's time) "
                "cannot pay for image.min_spp = %d now (%.3g s in the account, the run at %.3gx so far)",
                pass.cfg.global.budget, pass.cfg.global.budget, pass.spec.min_spp, budget ? budget->allowance() : 0.0,
                budget ? budget->ratio() : 0.0);
  r.warnings.emplace_back(buf);
  if ((n & (n - 1)) == 0)
    log_line("warning: render '" + r.name + "' at step " + std::to_string(r.step) + ": " + r.warnings.back() +
             (n > 1 ? " (" + std::to_string(n) + " calls in a row)" : std::string()));
  return out;
}

void finish(const PassContext& pass, const PreparedScene& prepared, const FieldPlan& plan, std::size_t views,
            bool quiet, PassOutcome& out) {
  const config::RenderSpec& spec = pass.spec;
  RenderResult& r = out.result;
  r.samples_per_second = r.render_seconds > 0.0 ? r.stats.samples / r.render_seconds : 0.0;
  r.actual_spp = static_cast<double>(r.stats.samples) /
                 (static_cast<double>(spec.image.width) * spec.image.height * static_cast<double>(1 + views));
  pass.render.budget_skips = 0;
  r.simulation_seconds = pass.call.simulation_seconds;
  r.cost_ratio = r.simulation_seconds > 0.0 ? r.render_seconds / r.simulation_seconds : 0.0;
  if (!pass.root()) return;
  if (!quiet) log_line(summary(pass, r));
  // Warnings about the image (rank 0 holds the stats summed over ranks): never a failure
  r.warnings = render_warnings(prepared, r.stats);
  if (plan.distributed && !plan.cache_warning.empty()) r.warnings.insert(r.warnings.begin(), plan.cache_warning);
  for (const std::string& w : r.warnings)
    log_line("warning: render '" + r.name + "' at step " + std::to_string(r.step) + ": " + w);
}

}  // namespace tessera::insitu
