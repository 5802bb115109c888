#pragma once
/// One render of one execute call, through its phases:
///   bind (descriptors -> FieldView) -> range (auto range / `when` maximum) -> memory and
///   distribution (replicated or distributed, docs/mpi.md) -> assemble or distribute
///   (ParallelContext) -> scene + prepare -> render (ParallelContext) -> write (rank 0)
///   [-> Cinema: prepare, render, write per camera -> data.csv].
/// The one pass over a field's values (its FieldSummary: majorant ranges, finite min/max) is
/// made at most once per field and call and shared by every render and camera that uses it;
/// none when the simulation marked the field unchanged (summary_cache.h).
/// After each phase the ranks agree (ParallelContext::agree) on success, so that every rank
/// takes the same path and none is left waiting in a collective. Nothing is prepared or read
/// for a render that does not fire.
#include "budget/render_budget.h"
#include "data/mesh_layout_keep.h"
#include "data/summary_cache.h"
#include "outputs/cinema.h"
#include "outputs/triggers.h"
#include "parallel/parallel_context.h"

#include <tessera/adapter.h>
#include <tessera/config/config.h>
#include <tessera/image.h>
#include <tessera/tessera.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace tessera::insitu {

/// A render of the config and what the adapter keeps about it between calls.
struct RenderState {
  explicit RenderState(const config::RenderSpec& s) : spec(&s), trigger(s.trigger) {}
  const config::RenderSpec* spec;
  Trigger trigger;
  std::optional<Image> last_image;         ///< rank 0: the last image rendered
  std::unique_ptr<CinemaDatabase> cinema;  ///< rank 0, created at first use
  int logged_mode = -1;                    ///< the field mode last logged (0 replicated, 1 distributed)
  int budget_skips = 0;                    ///< calls in a row the render budget skipped it
};

/// What one call publishes, valid during that call only: a grid and fields (tessera_execute)
/// or, for tessera_execute_domains, the mesh and this rank's domains (grid and fields unused).
struct Publication {
  const tessera_grid* grid = nullptr;
  const tessera_field* fields = nullptr;
  std::int64_t nfields = 0;
  bool domains_call = false;
  const tessera_mesh* mesh = nullptr;
  const tessera_domain* domains = nullptr;
  std::int64_t ndomains = 0;
  /// Set (descriptors all null): a language binding refused this rank's descriptors before the
  /// call (tessera_execute_refused); the bind phase fails with this reason, on every rank alike.
  const char* refusal = nullptr;
  /// tessera_execute_mesh_domains: curvilinear and unstructured domains (ndomains of them).
  bool mesh_call = false;
  const tessera_mesh_domain* mesh_domains = nullptr;
};

/// What one execute call derives from its descriptors, shared by its renders. Everything is
/// keyed by the render's `field:` name, which is the same on every rank.
struct CallData {
  std::int64_t step = 0;
  double time = 0.0;
  Publication pub;  ///< the call's descriptors
  /// The simulation's wall time since the last call that rendered (0 in the first call), this rank.
  double simulation_seconds = 0.0;
  /// tessera.budget: the plan every rank renders with (rank 0's, budget_planner.h); 1 (each
  /// render's spp) without a budget.
  double budget_plan = 1.0;
  /// tessera.budget: this rank's account, for the log line (rank 0's is the one that plans);
  /// nullptr without a budget.
  const RenderBudget* budget = nullptr;
  /// Global finite min/max per field, computed at most once per call.
  std::vector<std::pair<std::string, std::pair<double, double>>> ranges;
  /// A curvilinear or unstructured mesh's layout, kept from call to call (mesh_pass.h).
  MeshLayoutKeep mesh_layout;
  /// The last assembled field (valid until the next assemble).
  std::optional<std::string> assembled_key;
  FieldView assembled;
  /// The owner of `assembled` when it was assembled in device memory (one rank's device
  /// blocks, FieldDevice::assemble_on_device); freed with the call or the next assemble.
  std::shared_ptr<const void> assembled_device;
  /// Refinement levels: the last assembled hierarchy's patches (ParallelContext::assemble_amr;
  /// assembled_key names its field).
  std::vector<AmrPatch> assembled_patches;
  /// The simulation's CUDA stream (Adapter::set_cuda_stream), kept from call to call; null:
  /// Tessera synchronises the whole device before it reads device arrays.
  void* cuda_stream = nullptr;
};

struct PassOutcome {
  bool fired = false;        ///< false: a `when` trigger evaluated and did not fire
  bool report_here = false;  ///< this rank logs the failure (rank 0, or a failure only here)
  RenderResult result;
};

/// Runs `render` for `call`. check_when: the render fires only if its `when` trigger does.
/// `summaries`: the adapter's field summaries (summary_cache.h), used and updated; the call
/// must have begun with summaries.begin_call(). Never throws: failures come back in the
/// result (status + message naming render and step).
PassOutcome run_render(ParallelContext& ctx, const config::Config& cfg, RenderState& render, CallData& call,
                       SummaryCache& summaries, bool check_when, bool quiet) noexcept;

}  // namespace tessera::insitu
