#pragma once
/// Adapter::Impl: the adapter's state and its open / execute / close logic. Shared by the C++
/// class (adapter.cpp, which adds the `on_error: abort` rethrow) and the C API (c_api.cpp).
/// No member throws.
#include "agreement/call_gate.h"
#include "budget/render_budget.h"
#include "data/summary_cache.h"
#include "outputs/error_policy.h"
#include "outputs/output_claims.h"
#include "parallel/parallel_context.h"
#include "pass/render_pass.h"

#include <tessera/adapter.h>
#include <tessera/config/config.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace tessera::insitu {

struct Adapter::Impl {
  /// output_dir: replaces the config's tessera.output_dir after it has loaded and validated;
  /// nullptr or "" keeps the config's.
  /// yaml_text: the config's text (yaml_path names it in messages); nullptr = read yaml_path.
  tessera_status open(const char* yaml_path, int mpi_comm_f, const char* output_dir,
                      const std::string* yaml_text = nullptr) noexcept;
  /// fields/nfields as the C API receives them; checked only if a render fires.
  tessera_status execute(std::int64_t step, double time, const tessera_grid* grid, const tessera_field* fields,
                         std::int64_t nfields, bool final_step) noexcept;
  /// tessera_execute_domains: mesh, domains and ndomains as the C API receives them; checked
  /// only if a render fires (domain_binding.h, then the contexts' tiling check).
  tessera_status execute_domains(std::int64_t step, double time, const tessera_mesh* mesh,
                                 const tessera_domain* domains, std::int64_t ndomains, bool final_step) noexcept;
  /// tessera_execute_mesh_domains: curvilinear and unstructured domains as the C API receives
  /// them; checked only if a render fires (mesh_binding.h).
  tessera_status execute_mesh_domains(std::int64_t step, double time, const tessera_mesh_domain* domains,
                                      std::int64_t ndomains, bool final_step) noexcept;
  /// tessera_execute_refused: the call (0 grid, 1 domains, 2 mesh domains) with no
  /// descriptors, whose renders that fire fail with `reason` on this rank (non-null,
  /// NUL-terminated).
  tessera_status execute_refused(std::int64_t step, double time, int call_kind, const char* reason,
                                 bool final_step) noexcept;
  /// Collective with MPI: the ranks agree that every one of them is closing (one allgather
  /// of the call record, rank_agreement.h), so a rank still inside an execute call that
  /// fires is told so, and so is this one: TESSERA_ERROR_CONFIG with m_error saying which
  /// rank did what. Everything is released whatever the outcome. Skips the agreement when
  /// an earlier one found that a rank had closed already (it would wait forever).
  tessera_status close() noexcept;
  /// Releases everything without communicating (failure paths where the ranks have agreed).
  void teardown() noexcept;
  /// Adapter::field_unchanged / tessera_field_unchanged (field_name may be NULL: an error).
  tessera_status field_unchanged(const char* field_name) noexcept;
  /// Adapter::mesh_unchanged / tessera_mesh_unchanged.
  tessera_status mesh_unchanged() noexcept;
  /// Adapter::set_cuda_stream / tessera_set_cuda_stream.
  tessera_status set_cuda_stream(void* cuda_stream) noexcept;

  /// True once a config with `on_error: abort` is loaded.
  bool abort_mode() const { return m_ctx && m_policy.mode() == config::OnError::Abort; }

  config::Config m_config;
  std::unique_ptr<ParallelContext> m_ctx;  ///< null while not open
  std::vector<RenderState> m_renders;      ///< one per config render, pointing into m_config
  ErrorPolicy m_policy;
  std::string m_error;
  std::vector<RenderResult> m_results;
  bool m_quiet = false;
  bool m_closed = false;  ///< close() ended an open adapter (execute says so)
  /// Set when an agreement found that another rank has closed: every later execute returns
  /// it, and close skips its agreement.
  std::string m_broken;
  /// The C++ Adapter's gate (call_gate.h); the C API keeps its own in the handle.
  CallGate m_gate;

 private:
  tessera_status run_call(std::int64_t step, double time, const Publication& pub, bool final_step) noexcept;

  /// Read as bytes by the agreement (rank_agreement.h CallView::fired): keep these values.
  enum class Decision : unsigned char { Skip = 0, Fire = 1, WhenTrigger = 2 };

 public:
  /// Whether a call at `step` evaluates any render (Adapter::fires): the decision run_call
  /// takes first, from the config and the arguments alone. The adapter must be open.
  bool any_fires(std::int64_t step, bool final_step) const noexcept;

 private:
  /// Render i's decision for a call at `step` (force: final_step with render_final_step).
  Decision decide(std::size_t i, std::int64_t step, bool force) const noexcept;
  std::vector<Decision> m_decisions;  ///< per render, sized at open: no allocation per call
  CallData m_call;
  SummaryCache m_summaries;
  /// The simulation's time (wall, outside execute) since the last execute in which a render
  /// fired: m_sim_seconds so far, plus the time since m_sim_since (the return of the last
  /// execute) once the next execute starts. -1 from open() until the first execute returns:
  /// the first call has no simulation time to compare with.
  std::chrono::steady_clock::time_point m_sim_since{};
  double m_sim_seconds = 0.0;
  /// adapter_time_total() when this adapter's last call returned (or at open): what the
  /// process's adapters spent since then is not the simulation's time.
  double m_adapter_time_mark = 0.0;
  /// This adapter's output_dir, claimed while it is open (output_claims.h).
  OutputClaim m_claim;
  /// The call's mesh when the domains give axes in pieces (axis_pieces.h): the caller's, with
  /// those axes' coordinates in m_axes (kept during the call only).
  tessera_mesh m_call_mesh{};
  std::array<std::vector<double>, 3> m_axes;
  /// Gathers every rank's pieces and assembles the axes into m_call_mesh (collective); the
  /// message (the same on every rank) when they do not fit.
  std::optional<std::string> assemble_axes_of(const Publication& pub);

  // The phases of run_call, in order:
  /// Not open, broken by a rank that closed, or blocked by on_error: the status (m_error set).
  std::optional<tessera_status> refused_call();
  /// Each render's decision for the step into m_decisions; whether any may fire.
  bool decide_all(std::int64_t step, bool final_step);
  /// The ranks' agreement (and rank 0's budget plan into `plan`), then the axes the domains give
  /// in pieces; `call_pub` the publication the renders read. The status when it fails.
  std::optional<tessera_status> agree_call(std::int64_t step, bool final_step, const Publication& pub, double& plan,
                                           Publication& call_pub);
  /// m_call for this call's renders.
  void begin_call(std::int64_t step, double time, const Publication& pub, double plan);
  /// Every render that fires, in config order, through on_error; the call's status.
  tessera_status run_renders();
  /// Forgets the call's descriptors (valid during the call only).
  void end_call();
  /// tessera.budget: the account and the planner (render_budget.h); empty without a budget.
  std::optional<RenderBudget> m_budget;
};

}  // namespace tessera::insitu
