#include "adapter_impl.h"

#include "agreement/rank_agreement.h"
#include "budget/adapter_time.h"
#include "data/axis_pieces.h"
#include "outputs/outputs.h"

#include <tessera/denoiser.h>
#include <tessera/message_text.h>

#include <algorithm>
#include <filesystem>
#include <optional>

namespace tessera::insitu {

tessera_status Adapter::Impl::open(const char* yaml_path, int mpi_comm_f, const char* output_dir,
                                   const std::string* yaml_text) noexcept {
  close();  // an adapter open before: closed as close() does (collectively)
  try {
    // Communicator: duplicated only; the nodes are set up once the ranks agree (below)
    try {
      m_ctx = ParallelContext::create(mpi_comm_f);
    } catch (const std::exception& e) {
      m_error = std::string("cannot use MPI communicator ") + std::to_string(mpi_comm_f) + ": " + e.what();
      return TESSERA_ERROR_CONFIG;
    }

    // Config: loaded and fully validated on every rank; all fail if one does
    bool ok = true;
    std::string fault;
    std::string effective;  // the canonical text of the config as this rank will use it
    try {
      if (!yaml_path) throw std::invalid_argument("config path is NULL");
      m_config = yaml_text ? config::parse_config(*yaml_text, yaml_path, "") : config::load_config(yaml_path);
      if (output_dir && *output_dir) m_config.global.output_dir = output_dir;
      // Two adapters of this process never write the same files (output_claims.h)
      m_claim = OutputClaim(m_config.global.output_dir, m_config.path);
      // image.denoise: the library is found now, not after days of simulation (rank 0 denoises)
      for (std::size_t i = 0; i < m_config.renders.size() && m_ctx->rank() == 0; ++i) {
        if (!m_config.renders[i].image.denoise) continue;
        try {
          require_denoiser();
        } catch (const DenoiserUnavailable& e) {
          throw std::runtime_error(shown_path(m_config.path) + ": renders[" + std::to_string(i) +
                                   "].image.denoise (render '" + m_config.renders[i].name + "'): " + e.what());
        }
        break;
      }
      effective = config::to_yaml(m_config);
      // tessera.budget (and the fake clock of tests, TESSERA_TEST_CLOCK, whose value the
      // ranks compare below)
      m_budget.reset();
      if (m_config.global.budget > 0.0) m_budget.emplace(m_config);
    } catch (const std::exception& e) {
      ok = false;
      fault = e.what();
    }
    if (!m_ctx->agree(ok)) {
      m_error = ok ? "the config failed to load on another rank" : fault;
      teardown();
      return TESSERA_ERROR_CONFIG;
    }

    // Ranks agree on the effective config and the environment before anything depends on
    // them; then the nodes (TESSERA_MPI_RANKS_PER_NODE, now known to be the same everywhere)
    if (std::optional<Disagreement> d = agree_on_open(*m_ctx, effective)) {
      m_error = std::move(d->message);
      teardown();
      return d->status;
    }
    try {
      m_ctx->connect();
    } catch (const std::exception& e) {
      ok = false;
      fault = e.what();
    }
    if (!m_ctx->agree(ok)) {
      m_error = ok ? "the MPI nodes could not be set up on another rank" : fault;
      teardown();
      return TESSERA_ERROR_CONFIG;
    }
    m_policy = ErrorPolicy(m_config.global.on_error, m_config.global.max_failures, m_config.renders.size());

    // Output directory and the effective config, written by rank 0
    try {
      if (m_ctx->rank() == 0) {
        ensure_directory(m_config.global.output_dir);
        write_text_atomic(
            (std::filesystem::path(m_config.global.output_dir) / "tessera_effective_config.yaml").string(), effective);
      }
    } catch (const std::exception& e) {
      ok = false;
      fault = e.what();
    }
    if (!m_ctx->agree(ok)) {
      // (a long output_dir is quoted short, however often the message names it)
      m_error = ok ? "rank 0 could not write the effective config"
                   : message_quoting(std::move(fault), m_config.global.output_dir);
      m_policy = ErrorPolicy();
      teardown();
      return TESSERA_ERROR_IO;
    }

    m_renders.reserve(m_config.renders.size());
    for (const config::RenderSpec& spec : m_config.renders) m_renders.emplace_back(spec);
    m_decisions.assign(m_renders.size(), Decision::Skip);
    m_error.clear();
    m_closed = false;
    m_sim_seconds = -1.0;  // unknown until the first execute has returned
    m_sim_since = std::chrono::steady_clock::now();
    m_adapter_time_mark = adapter_time_total();
    return TESSERA_OK;
  } catch (const std::exception& e) {
    m_error = std::string("tessera_open: ") + e.what();
  } catch (...) {
    m_error = "tessera_open: unknown exception";
  }
  teardown();
  return TESSERA_ERROR_CONFIG;
}

tessera_status Adapter::Impl::execute(std::int64_t step, double time, const tessera_grid* grid,
                                      const tessera_field* fields, std::int64_t nfields, bool final_step) noexcept {
  Publication pub;
  pub.grid = grid;
  pub.fields = fields;
  pub.nfields = nfields;
  return run_call(step, time, pub, final_step);
}

tessera_status Adapter::Impl::execute_domains(std::int64_t step, double time, const tessera_mesh* mesh,
                                              const tessera_domain* domains, std::int64_t ndomains,
                                              bool final_step) noexcept {
  Publication pub;
  pub.domains_call = true;
  pub.mesh = mesh;
  pub.domains = domains;
  pub.ndomains = ndomains;
  return run_call(step, time, pub, final_step);
}

tessera_status Adapter::Impl::execute_mesh_domains(std::int64_t step, double time, const tessera_mesh_domain* domains,
                                                   std::int64_t ndomains, bool final_step) noexcept {
  Publication pub;
  pub.mesh_call = true;
  pub.mesh_domains = domains;
  pub.ndomains = ndomains;
  return run_call(step, time, pub, final_step);
}

tessera_status Adapter::Impl::execute_refused(std::int64_t step, double time, int call_kind, const char* reason,
                                              bool final_step) noexcept {
  Publication pub;
  pub.domains_call = call_kind == 1;
  pub.mesh_call = call_kind == 2;
  pub.refusal = reason;
  return run_call(step, time, pub, final_step);
}

std::optional<std::string> Adapter::Impl::assemble_axes_of(const Publication& pub) {
  bool ok = true;
  std::string fault;
  try {
    const std::vector<std::string> all =
        m_ctx->allgather_bytes(pack_pieces(*pub.mesh, pub.domains, pub.ndomains), max_piece_bytes(*pub.mesh));
    m_axes = assemble_axes(*pub.mesh, all);  // the same verdict on every rank: every rank has every piece
    m_call_mesh = *pub.mesh;
    for (int a = 0; a < 3; ++a)
      if (!m_axes[a].empty()) m_call_mesh.coords[a] = m_axes[a].data();
    m_call_mesh.axes_from_domains = 0;
  } catch (const std::exception& e) {
    ok = false;
    fault = e.what();
  }
  if (m_ctx->agree(ok)) return std::nullopt;
  return ok ? std::string("the axes the domains give in pieces could not be assembled on another rank") : fault;
}

Adapter::Impl::Decision Adapter::Impl::decide(std::size_t i, std::int64_t step, bool force) const noexcept {
  const Trigger& t = m_renders[i].trigger;
  return force                   ? Decision::Fire
         : t.needs_field_max()   ? Decision::WhenTrigger
         : t.fires_on_step(step) ? Decision::Fire
                                 : Decision::Skip;
}

bool Adapter::Impl::any_fires(std::int64_t step, bool final_step) const noexcept {
  const bool force = final_step && m_config.global.render_final_step;
  for (std::size_t i = 0; i < m_renders.size(); ++i)
    if (decide(i, step, force) != Decision::Skip) return true;
  return false;
}

std::optional<tessera_status> Adapter::Impl::refused_call() {
  if (!m_ctx) {
    m_error = m_closed ? "adapter was closed: execute after close" : "the adapter is not open";
    return TESSERA_ERROR_CONFIG;
  }
  if (!m_broken.empty()) {
    m_error = m_broken;
    return TESSERA_ERROR_CONFIG;
  }
  if (m_policy.blocked()) {
    m_error = m_policy.blocked_message();
    return m_policy.blocked_status();
  }
  return std::nullopt;
}

bool Adapter::Impl::decide_all(std::int64_t step, bool final_step) {
  const bool force = final_step && m_config.global.render_final_step;
  bool any = false;
  for (std::size_t i = 0; i < m_renders.size(); ++i) {
    m_decisions[i] = decide(i, step, force);
    any = any || m_decisions[i] != Decision::Skip;
  }
  return any;
}

std::optional<tessera_status> Adapter::Impl::agree_call(std::int64_t step, bool final_step, const Publication& pub,
                                                        double& plan, Publication& call_pub) {
  // Ranks agree on the step, the renders that fire and the grid, before any other
  // collective; with a budget every rank adopts rank 0's plan for the call in the same step
  const bool root = m_ctx->rank() == 0;
  const std::span<const unsigned char> fired{reinterpret_cast<const unsigned char*>(m_decisions.data()),
                                             m_decisions.size()};
  plan = m_budget ? m_budget->plan(step, std::max(0.0, m_sim_seconds), fired) : 1.0;
  CallView view{final_step ? CallKind::Final : CallKind::Execute, step, fired, m_config.renders, pub.grid, plan};
  view.domains_call = pub.domains_call;
  view.mesh_call = pub.mesh_call;
  view.mesh = pub.mesh;
  view.domains = pub.domains;
  view.ndomains = pub.ndomains;
  int pieced_axes = 0;
  if (std::optional<Disagreement> d = agree_on_call(*m_ctx, view, kAgreementWarnSeconds, &plan, &pieced_axes)) {
    if (root) log_line(d->message);
    if (d->rank_closed) m_broken = d->message;
    m_error = std::move(d->message);
    return d->status;
  }
  // Axes the domains give in pieces: assembled on every rank alike, then the call's mesh
  call_pub = pub;
  if (pieced_axes != 0) {
    if (std::optional<std::string> fault = assemble_axes_of(pub)) {
      m_error = "step " + std::to_string(step) + ": " + std::move(*fault);
      if (root) log_line(m_error);
      return TESSERA_ERROR_DATA;
    }
    call_pub.mesh = &m_call_mesh;
  }
  return std::nullopt;
}

void Adapter::Impl::begin_call(std::int64_t step, double time, const Publication& pub, double plan) {
  m_call.step = step;
  m_call.time = time;
  m_call.pub = pub;
  m_call.simulation_seconds = std::max(0.0, m_sim_seconds);
  m_call.budget_plan = plan;
  m_call.budget = m_budget ? &*m_budget : nullptr;
  m_call.ranges.clear();
  m_call.assembled_key.reset();
}

tessera_status Adapter::Impl::run_renders() {
  // Renders that fire (or may: `when`), in config order
  const bool root = m_ctx->rank() == 0;
  tessera_status status = TESSERA_OK;
  const config::RenderSpec* skipped = nullptr;  // a disabled render that would have fired
  for (std::size_t i = 0; i < m_renders.size() && !m_policy.blocked(); ++i) {
    if (m_decisions[i] == Decision::Skip) continue;
    if (m_policy.disabled(i)) {
      if (m_decisions[i] == Decision::Fire && !skipped) skipped = m_renders[i].spec;
      continue;
    }
    const auto pass_start = std::chrono::steady_clock::now();
    PassOutcome out = run_render(*m_ctx, m_config, m_renders[i], m_call, m_summaries,
                                 m_decisions[i] == Decision::WhenTrigger, m_quiet);
    if (!out.fired) continue;
    if (m_budget)
      m_budget->record(i, out.result,
                       std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count());
    if (out.result.budget_skipped) {
      // neither a success nor a failure for on_error
    } else if (out.result.status == TESSERA_OK) {
      m_policy.record_success(i);
    } else {
      if (out.report_here) log_line(out.result.error);
      if (m_policy.record_failure(i, out.result.status, out.result.error) && root)
        log_line("render '" + m_renders[i].spec->name + "' disabled after " + std::to_string(m_policy.max_failures()) +
                 " consecutive failures (on_error: disable)");
      if (status == TESSERA_OK) {
        status = out.result.status;
        m_error = out.result.error;
      }
    }
    m_results.push_back(std::move(out.result));
  }
  if (m_policy.blocked() && root) log_line(m_policy.blocked_message());
  if (status == TESSERA_OK && skipped) {
    status = TESSERA_ERROR_DISABLED;
    m_error = "render '" + skipped->name + "' is disabled after " + std::to_string(m_policy.max_failures()) +
              " consecutive failures (on_error: disable)";
  }
  return status;
}

void Adapter::Impl::end_call() {
  // The descriptors are only valid during this call
  m_call.pub = Publication{};
  m_call.assembled_key.reset();
  m_call.assembled = FieldView{};
  m_call.assembled_device.reset();  // a replica on the device: its memory back to the simulation
  m_call.assembled_patches.clear();
  for (std::vector<double>& axis : m_axes) axis.clear();
}

tessera_status Adapter::Impl::run_call(std::int64_t step, double time, const Publication& pub,
                                       bool final_step) noexcept {
  // The simulation's time since the last call, added on entry: the wall time less what any
  // other adapter of the process spent meanwhile (adapter_time.h: their rendering is never
  // the simulation's time). On every return the clock restarts, this call's time joins the
  // process's sum, and a call in which a render fired starts the sum afresh
  const auto entry = std::chrono::steady_clock::now();
  if (m_sim_seconds >= 0.0) {
    const double elapsed = std::chrono::duration<double>(entry - m_sim_since).count();
    m_sim_seconds += std::max(0.0, elapsed - (adapter_time_total() - m_adapter_time_mark));
  }
  struct SimClock {
    Impl& impl;
    std::chrono::steady_clock::time_point entry;
    ~SimClock() {
      if (impl.m_sim_seconds < 0.0 || !impl.m_results.empty()) impl.m_sim_seconds = 0.0;
      impl.m_sim_since = std::chrono::steady_clock::now();
      add_adapter_time(std::chrono::duration<double>(impl.m_sim_since - entry).count());
      impl.m_adapter_time_mark = adapter_time_total();
    }
  } sim_clock{*this, entry};
  try {
    m_results.clear();
    m_error.clear();
    // A mesh call counts whatever becomes of it: a mesh_unchanged mark says "as at the last
    // call" (mesh_layout_keep.h)
    if (pub.mesh_call) m_call.mesh_layout.begin_call();
    if (const std::optional<tessera_status> refused = refused_call()) return *refused;
    // field_unchanged marks apply to this call only, whether a render fires or not
    m_summaries.begin_call();
    // Triggers, decided from the step alone where possible: no field memory touched yet
    if (!decide_all(step, final_step)) return TESSERA_OK;  // no communication: identical configs decide alike
    const auto call_start = std::chrono::steady_clock::now();
    double plan = 1.0;
    Publication call_pub;
    if (const std::optional<tessera_status> failed = agree_call(step, final_step, pub, plan, call_pub)) return *failed;
    begin_call(step, time, call_pub, plan);
    const tessera_status status = run_renders();
    if (m_budget)
      m_budget->end_call(std::chrono::duration<double>(std::chrono::steady_clock::now() - call_start).count(),
                         m_results);
    end_call();
    return status;
  } catch (const std::exception& e) {
    try {
      m_error = std::string("tessera_execute: ") + e.what();
    } catch (...) {
    }
  } catch (...) {
    try {
      m_error = "tessera_execute: unknown exception";
    } catch (...) {
    }
  }
  return TESSERA_ERROR_RENDER;
}

tessera_status Adapter::Impl::field_unchanged(const char* field_name) noexcept {
  try {
    m_error.clear();
    if (!m_ctx) {
      m_error = "field_unchanged: the adapter is not open";
      return TESSERA_ERROR_CONFIG;
    }
    if (!field_name) {
      m_error = "field_unchanged: field name is NULL";
      return TESSERA_ERROR_DATA;
    }
    // A render names the field, or takes the only published field (any name)
    std::string names;
    for (const config::RenderSpec& r : m_config.renders) {
      if (r.uses(field_name)) {
        m_summaries.mark_unchanged(field_name);
        return TESSERA_OK;
      }
      if (names.find("'" + r.field + "'") == std::string::npos) names += (names.empty() ? "'" : ", '") + r.field + "'";
    }
    m_error = std::string("field_unchanged: no render uses a field called '") + shown_value(field_name) +
              "' (the config's renders use " + names + ")";
    return TESSERA_ERROR_DATA;
  } catch (...) {
    m_error.clear();  // out of memory for the message: the status alone tells
  }
  return TESSERA_ERROR_DATA;
}

tessera_status Adapter::Impl::mesh_unchanged() noexcept {
  m_error.clear();
  if (!m_ctx) {
    m_error = "mesh_unchanged: the adapter is not open";
    return TESSERA_ERROR_CONFIG;
  }
  m_call.mesh_layout.marked = true;
  return TESSERA_OK;
}

tessera_status Adapter::Impl::set_cuda_stream(void* cuda_stream) noexcept {
  m_error.clear();
  if (!m_ctx) {
    m_error = "set_cuda_stream: the adapter is not open";
    return TESSERA_ERROR_CONFIG;
  }
  m_call.cuda_stream = cuda_stream;
  return TESSERA_OK;
}

tessera_status Adapter::Impl::close() noexcept {
  tessera_status status = TESSERA_OK;
  if (m_ctx && m_broken.empty() && m_ctx->size() > 1 && m_ctx->can_communicate()) {
    try {
      const CallView view{CallKind::Close, 0, {}, m_config.renders, nullptr};
      if (std::optional<Disagreement> d = agree_on_call(*m_ctx, view)) {
        if (m_ctx->rank() == 0) log_line(d->message);
        m_error = std::move(d->message);
        status = d->status;
      }
    } catch (const std::exception& e) {
      try {
        m_error = std::string("tessera_close: ") + e.what();
      } catch (...) {
      }
      status = TESSERA_ERROR_RENDER;
    }
  }
  teardown();
  return status;
}

void Adapter::Impl::teardown() noexcept {
  if (m_ctx) m_closed = true;
  m_broken.clear();
  m_results.clear();
  m_summaries.clear();
  m_renders.clear();
  m_decisions.clear();
  m_call = CallData{};
  m_budget.reset();
  m_claim = OutputClaim();
  try {
    m_ctx.reset();
  } catch (...) {
    // A context that cannot be released cleanly is dropped all the same
  }
}

}  // namespace tessera::insitu
