#include "render_pass.h"

#include "amr_layout.h"
#include "block_ops.h"
#include "domain_binding.h"
#include "error_policy.h"
#include "field_binding.h"
#include "field_plan.h"
#include "outputs.h"

#include <tessera/config/build_scene.h>
#include <tessera/denoiser.h>
#include <tessera/film.h>
#include <tessera/image_format.h>
#include <tessera/image_io.h>
#include <tessera/memory_estimate.h>
#include <tessera/message_text.h>
#include <tessera/render.h>
#include <tessera/scene_warnings.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <thread>

namespace tessera::insitu {
namespace {

using Clock = std::chrono::steady_clock;

/// Global finite min/max of a field: this rank's finite values (all its blocks), then
/// ParallelContext::range. A rank without finite values contributes nothing; with none
/// anywhere, lo > hi.
std::pair<double, double> global_range(ParallelContext& ctx, std::span<const FieldBlock> blocks) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const auto [lo, hi] = blocks_range(blocks).value_or(std::pair{kInf, -kInf});
  return ctx.range(lo, hi);
}

/// The phases of one render on this rank.
class Pass {
 public:
  Pass(ParallelContext& ctx, const config::Config& cfg, RenderState& render, CallData& call, SummaryCache& summaries)
      : m_ctx(ctx),
        m_cfg(cfg),
        m_render(render),
        m_spec(*render.spec),
        m_call(call),
        m_summaries(summaries),
        m_start(Clock::now()),
        m_spp(planned_spp(call.budget_plan, BudgetLimits{render.spec->image.spp, render.spec->min_spp})) {
    // tessera.time_limit: one deadline for the whole run, every Cinema view included
    if (cfg.global.time_limit > 0.0)
      m_deadline =
          m_start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(cfg.global.time_limit));
    m_out.result.name = m_spec.name;
    m_out.result.step = call.step;
    m_out.result.time = call.time;
    m_out.result.planned_spp = m_spp;
    m_out.result.budget = cfg.global.budget;
  }

  PassOutcome run(bool check_when, bool quiet) {
    const bool root = m_ctx.rank() == 0;
    m_out.fired = true;
    // The render budget cannot give this render min_spp: skipped before any work (a `when`
    // render once its trigger has fired)
    if (m_spp == 0 && !check_when) return skipped();

    // Bind: descriptors -> zero-copy view of this rank's real vertices (a binding's refusal
    // stands in for this rank's bind: the reason, not a complaint about missing descriptors)
    if (m_call.pub.refusal) {
      phase(TESSERA_ERROR_DATA, [&] { throw std::invalid_argument(m_call.pub.refusal); });
      return std::move(m_out);
    }
    if (m_call.pub.domains_call) {
      if (!bind_domains_phase()) return std::move(m_out);
    } else if (!phase(TESSERA_ERROR_DATA, [&] {
                 if (m_call.pub.nfields < 0 || (m_call.pub.nfields > 0 && !m_call.pub.fields))
                   throw std::invalid_argument(
                       "field list is invalid (fields = " + std::string(m_call.pub.fields ? "non-null" : "NULL") +
                       ", nfields = " + std::to_string(m_call.pub.nfields) + ")");
                 if (!m_call.pub.grid) throw std::invalid_argument("grid descriptor is NULL");
                 const std::span<const tessera_field> fields(m_call.pub.fields,
                                                             static_cast<std::size_t>(m_call.pub.nfields));
                 const tessera_field& f = fields[find_field(fields, m_spec.field, m_spec.name)];
                 m_binding = bind_field(f, *m_call.pub.grid);
                 if (m_ctx.size() == 1) require_whole_grid(f, m_binding);
                 m_field_name = f.name;
               }))
      return std::move(m_out);

    // Refinement levels: every rank's boxes checked as one hierarchy, on every rank alike
    if (m_binding.nlevels > 1 && !phase(TESSERA_ERROR_DATA, [&] {
          m_amr = m_ctx.amr_layout(m_binding.blocks, amr_meta(m_binding, m_binding.local.dtype),
                                   m_binding.geometry.association);
        }))
      return std::move(m_out);

    // Summaries carried from the last call: kept only if every rank may keep them
    SummaryCache::Entry& entry = m_summaries.entry(m_field_name);
    if (!entry.decided) {
      const SummaryKey key = SummaryKey::of(m_binding);
      const bool keep = m_ctx.agree(entry.carried && !entry.summaries.empty() && entry.key == key);
      if (!keep) entry.summaries.clear();
      entry.kept = keep;
      entry.key = key;
      entry.decided = true;
    }

    // Range: only when the trigger or `range: auto` needs it, once per field and call
    const bool need_range = check_when || m_spec.transfer_function.range.automatic;
    std::pair<double, double> range{0.0, 0.0};
    if (need_range) {
      if (!phase(TESSERA_ERROR_RENDER, [&] { range = cached_range(); })) return std::move(m_out);
      if (check_when && !m_render.trigger.fires_on_max(range.second)) {
        m_out.fired = false;
        return std::move(m_out);
      }
      if (!(range.first <= range.second)) range = {0.0, 0.0};  // no finite value anywhere
    }
    if (m_spp == 0) return skipped();

    // Memory and distribution: the render's own allocations (replica or brick cache, film,
    // images, envmap), estimated before any of them is made; after the `when` decision, so a
    // render that does not fire is not refused. `auto` is decided on every rank, then agreed.
    if (!phase(TESSERA_ERROR_RENDER, [&] {
          m_plan = plan_field(m_cfg, m_spec, m_binding, m_ctx.size(), m_ctx.ranks_on_node(), root,
                              m_amr ? &*m_amr : nullptr);
        }))
      return std::move(m_out);
    if (m_cfg.global.distribution == config::Distribution::Auto && m_ctx.size() > 1)
      m_plan.distributed = m_ctx.any(m_plan.distributed);
    // (the same answer on every rank: the config is the same and `auto` stays replicated)
    if (m_plan.distributed) {
      const AmrLayout* amr = m_amr ? &*m_amr : nullptr;
      if (!phase(TESSERA_ERROR_RENDER, [&] { plan_distributed(m_plan, m_binding, 0, amr); })) return std::move(m_out);
      // One brick cut for all: the finest any rank chose (their limits may differ). Every rank
      // takes part in the phase (it ends in a collective), re-planning only where it differs
      const int agreed = m_ctx.min(m_plan.shift);
      if (!phase(TESSERA_ERROR_RENDER, [&] {
            if (agreed != m_plan.shift) plan_distributed(m_plan, m_binding, agreed, amr);
          }))
        return std::move(m_out);
    }
    if (root && m_ctx.size() > 1 && m_render.logged_mode != (m_plan.distributed ? 1 : 0)) {
      m_render.logged_mode = m_plan.distributed ? 1 : 0;
      if (!quiet) log_line("render '" + m_spec.name + "': " + describe_plan(m_plan, m_cfg.global.distribution));
    }

    // The global field: assembled once per consecutive use (zero copy on one rank), or in
    // distributed mode this rank's block and a cache for the other ranks' bricks
    if (!phase(TESSERA_ERROR_RENDER, [&] {
          if (m_plan.distributed && m_amr) {
            // Refinement levels: every rank's patches paged through one virtual grid
            m_call.assembled_key.reset();
            const AmrVirtualLayout v = m_amr->virtual_grid();
            const std::vector<FieldBlock> ordered = in_domain_order(m_binding.blocks);
            m_call.assembled_patches = patches_distributed(ordered, *m_amr, m_ctx.rank());
            m_paged = m_ctx.distribute_amr(virtual_blocks(ordered, v), virtual_records(*m_amr, v), v.dims,
                                           m_amr->meta.dtype, m_plan.shift, m_plan.capacity);
            m_virtual = v;
          } else if (m_plan.distributed) {
            m_call.assembled_key.reset();  // distribute() frees the replica
            m_paged = m_ctx.distribute_blocks(m_binding.blocks, m_binding.placement.global_dims, m_binding.local.dtype,
                                              m_plan.shift, m_plan.capacity);
          } else if (m_amr) {
            if (m_call.assembled_key != m_spec.field) {
              m_call.assembled_key.reset();
              m_call.assembled_patches = m_ctx.assemble_amr(m_binding.blocks, *m_amr);
              m_call.assembled_key = m_spec.field;
            }
          } else if (m_call.assembled_key != m_spec.field) {
            m_call.assembled_key.reset();
            m_call.assembled =
                m_ctx.assemble_blocks(m_binding.blocks, m_binding.placement.global_dims, m_binding.local.dtype);
            m_call.assembled_key = m_spec.field;
          }
        }))
      return std::move(m_out);

    // Scene and preparation (camera, lights, envmap, majorants)
    SceneDesc scene;
    PreparedScene prepared;
    std::vector<CinemaView> views;
    if (!phase(TESSERA_ERROR_RENDER, [&] {
          scene = config::build_scene(m_spec, m_binding.global_bounds, range, m_binding.geometry, m_call.step);
          scene.options = config::build_render_options(m_spec, m_cfg.global);
          scene.options.frame = static_cast<std::uint64_t>(m_call.step);
          scene.options.deadline = m_deadline;
          scene.image.spp = m_spp;  // the render budget's plan (image.spp without one)
          if (m_spec.output.cinema) views = cinema_views(*m_spec.output.cinema, scene.camera, m_binding.global_bounds);
        }))
      return std::move(m_out);
    if (!phase(TESSERA_ERROR_RENDER, [&] { prepared = prepare_scene(scene); })) return std::move(m_out);

    // The render's own camera
    Film film;
    if (!render_film(prepared, film)) return std::move(m_out);
    Image img;
    if (!resolve_image(film, img)) return std::move(m_out);
    if (!phase(TESSERA_ERROR_IO, [&] {
          if (!root) return;
          const std::optional<AnnotationDesc> notes = annotations(scene);
          write_image_files(output_base(m_cfg.global.output_dir, m_spec, m_call.step, m_call.time, 0), m_spec.output,
                            img, m_out.result.files, notes ? &*notes : nullptr);
          m_render.last_image = std::move(img);
        }))
      return std::move(m_out);

    // Cinema sweep
    if (m_spec.output.cinema && !run_cinema(scene, views)) return std::move(m_out);

    RenderResult& r = m_out.result;
    r.samples_per_second = r.render_seconds > 0.0 ? r.stats.samples / r.render_seconds : 0.0;
    r.actual_spp = static_cast<double>(r.stats.samples) / (static_cast<double>(m_spec.image.width) *
                                                           m_spec.image.height * static_cast<double>(1 + views.size()));
    m_render.budget_skips = 0;
    r.simulation_seconds = m_call.simulation_seconds;
    r.cost_ratio = r.simulation_seconds > 0.0 ? r.render_seconds / r.simulation_seconds : 0.0;
    if (root && !quiet) log_line(summary());
    // Warnings about the image (rank 0 holds the stats summed over ranks): never a failure
    if (root) {
      r.warnings = render_warnings(prepared, r.stats);
      if (m_plan.distributed && !m_plan.cache_warning.empty())
        r.warnings.insert(r.warnings.begin(), m_plan.cache_warning);
      for (const std::string& w : r.warnings)
        log_line("warning: render '" + r.name + "' at step " + std::to_string(r.step) + ": " + w);
    }
    return std::move(m_out);
  }

 private:
  /// Runs fn on this rank, then agrees with the others; on any rank's failure records
  /// `status` and the message (this rank's own, or that another rank failed) and returns false.
  /// The other ranks' message quotes the first failing rank's.
  /// A LayoutError on any rank (the ranks' boxes do not fit together) records
  /// TESSERA_ERROR_DATA instead, on every rank: a descriptor fault, whichever phase found it.
  template <class Fn>
  bool phase(tessera_status status, Fn&& fn) {
    bool ok = true, layout = false;
    std::string fault;
    try {
      fn();
    } catch (const LayoutError& e) {
      ok = false;
      layout = true;
      fault = e.what();
    } catch (const std::exception& e) {
      ok = false;
      fault = e.what();
    } catch (...) {
      ok = false;
      fault = "unknown exception";
    }
    if (m_ctx.agree(ok)) return true;
    // Rank 0 logs every failure; another rank only one of its own that rank 0 did not share.
    // Two extra reductions, on the failure path only: whether some rank's fault is a
    // LayoutError, and whether rank 0 failed
    const bool root = m_ctx.rank() == 0;
    const bool any_layout = m_ctx.any(layout);
    const bool root_failed = m_ctx.any(root && !ok);
    // The first failing rank's own message, for the others' (two more collectives)
    const int first_failed = m_ctx.min(ok ? std::numeric_limits<int>::max() : m_ctx.rank());
    std::string theirs = ok ? std::string() : fault;
    m_ctx.broadcast(theirs, first_failed);
    m_out.report_here = root || (!ok && !root_failed);
    m_out.result.status = any_layout ? TESSERA_ERROR_DATA : status;
    // A long output_dir is quoted short (each time), and nothing prints raw
    fault = message_quoting(std::move(fault), m_cfg.global.output_dir);
    std::string where = "render '" + m_spec.name + "' at step " + std::to_string(m_call.step) + ": ";
    if (ok)
      m_out.result.error = where + "failed on another rank (rank " + std::to_string(first_failed) + ": " +
                           message_quoting(std::move(theirs), m_cfg.global.output_dir) + ")";
    else if (m_ctx.size() > 1) m_out.result.error = where + "rank " + std::to_string(m_ctx.rank()) + ": " + fault;
    else m_out.result.error = where + fault;
    return false;
  }

  /// tessera_execute_domains: binds this rank's domains (domain_binding.h), then the ranks
  /// agree on the field's dtype (a rank without domains learns it; ranks whose dtypes differ,
  /// or no domain anywhere, fail alike on every rank with TESSERA_ERROR_DATA).
  bool bind_domains_phase() {
    if (!phase(TESSERA_ERROR_DATA, [&] {
          m_binding = bind_domains(m_call.pub.mesh, m_call.pub.domains, m_call.pub.ndomains, m_spec.field, m_spec.name);
          m_field_name = m_spec.field;
          if (!m_binding.blocks.empty()) {
            const std::span<const tessera_field> fields(m_call.pub.domains[0].fields,
                                                        static_cast<std::size_t>(m_call.pub.domains[0].nfields));
            m_field_name = fields[find_field(fields, m_spec.field, m_spec.name)].name;
          }
        }))
      return false;
    return phase(TESSERA_ERROR_DATA, [&] {
      constexpr int kNone = std::numeric_limits<int>::max();
      const bool has = !m_binding.blocks.empty();
      const int mine = has ? static_cast<int>(m_binding.local.dtype) : kNone;
      const int lo = m_ctx.min(mine);
      const int hi = -m_ctx.min(has ? -mine : kNone);  // the largest over the ranks with domains
      if (lo == kNone)
        throw LayoutError("no rank passed a domain (ndomains = 0 everywhere): the domains must cover the mesh");
      if (lo != hi)
        throw LayoutError("ranks publish field '" + m_field_name + "' with different dtypes (" +
                          dtype_name(static_cast<DType>(lo)) + " and " + dtype_name(static_cast<DType>(hi)) + ")");
      m_binding.local.dtype = static_cast<DType>(lo);
    });
  }

  /// Throws the time-limit failure: the limit, the time taken, the tiles finished.
  [[noreturn]] void time_limit_passed(const DeadlineExceeded& e) const {
    char buf[192];
    std::snprintf(buf, sizeof buf, "passed tessera.time_limit = %g s after %.2f s (%zu/%zu tiles done)",
                  m_cfg.global.time_limit, std::chrono::duration<double>(Clock::now() - m_start).count(),
                  e.tiles_done(), e.tiles_total());
    throw std::runtime_error(buf);
  }

  std::pair<double, double> cached_range() {
    for (const auto& [key, range] : m_call.ranges)
      if (key == m_spec.field) return range;
    // From a summary of the global field: one kept from the last call (agreed by all ranks,
    // so all skip the reduction alike), or on one rank, where the global field is this
    // rank's view, the one this call made or makes now for prepare; else a pass here
    SummaryCache::Entry& entry = m_summaries.entry(m_field_name);
    // (One rank with several domains, or levels: no summary of the whole field before the
    // replica; whole() is false with levels)
    const bool whole = m_ctx.size() == 1 && m_binding.whole();
    std::shared_ptr<const FieldSummary> s = entry.kept || whole ? entry.find(0) : nullptr;
    if (!s && whole) {
      s = FieldSummary::build(m_binding.local, majorant_edge(m_binding.local, m_spec.integrator.desc));
      ++m_out.result.field_passes;
      entry.keep(s);
    }
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const auto range = !s                ? global_range(m_ctx, m_binding.blocks)
                       : s->has_finite() ? std::pair{s->value_min(), s->value_max()}
                                         : std::pair{kInf, -kInf};
    m_call.ranges.emplace_back(m_spec.field, range);
    return range;
  }

  /// prepare() (scene.options.deadline set) with the field's summary for the scene's macrocell edge when there is one;
  /// keeps a summary it had to make for the next prepare of the field.
  PreparedScene prepare_scene(const SceneDesc& scene) {
    SummaryCache::Entry& entry = m_summaries.entry(m_field_name);
    const auto t0 = Clock::now();
    PreparedScene prepared;
    try {
      if (m_plan.distributed && m_amr) {
        // Refinement levels, distributed: the summary from every rank's parts (collective,
        // unless one was kept), the other ranks' patches through the cache
        AmrField field = m_amr->meta;
        field.patches = m_call.assembled_patches;
        field.cache = m_paged.cache;
        field.layout = m_virtual;
        FieldView level0;
        level0.dtype = field.dtype;
        for (int a = 0; a < 3; ++a) level0.dims[a] = field.dims[a];
        const int edge = majorant_edge(level0, scene.integrator);
        std::shared_ptr<const FieldSummary> summary = entry.find(edge);
        if (!summary) {
          FieldSummary::Parts parts = amr_summary_parts(field, m_amr->assoc, edge);
          m_ctx.reduce_parts(parts);
          FieldLayout layout;
          layout.dtype = field.dtype;
          for (int a = 0; a < 3; ++a) layout.dims[a] = field.dims[a];
          summary = FieldSummary::from_parts(std::move(parts), layout, edge);
        }
        m_ctx.serve_while([&] { prepared = prepare(field, scene, summary); });
      } else if (m_plan.distributed) {
        // The global summary from every rank's block (collective), unless one was kept; the
        // adaptive preview in prepare reads the field, so it runs while the ranks serve bricks
        FieldView global = m_binding.local;
        for (int a = 0; a < 3; ++a) global.dims[a] = m_binding.placement.global_dims[a];
        const int edge = majorant_edge(global, scene.integrator);
        std::shared_ptr<const FieldSummary> summary = entry.find(edge);
        if (!summary)
          summary =
              m_ctx.summarize_blocks(m_binding.blocks, m_binding.placement.global_dims, m_binding.local.dtype, edge);
        m_ctx.serve_while([&] { prepared = prepare(m_paged, scene, summary); });
      } else if (m_amr) {
        // Refinement levels: the hierarchy, its summary (amr_summary) at level 0's edge
        AmrField field = m_amr->meta;
        field.patches = m_call.assembled_patches;
        FieldView level0;
        level0.dtype = field.dtype;
        for (int a = 0; a < 3; ++a) level0.dims[a] = field.dims[a];
        prepared = prepare(field, scene, entry.find(majorant_edge(level0, scene.integrator)));
      } else {
        prepared = prepare(m_call.assembled, scene, entry.find(majorant_edge(m_call.assembled, scene.integrator)));
      }
    } catch (const DeadlineExceeded& e) {  // the adaptive preview ran past the time limit
      time_limit_passed(e);
    }
    m_out.result.prepare_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    if (!prepared.summary_reused()) {
      ++m_out.result.field_passes;
      entry.keep(prepared.summary());
    }
    return prepared;
  }

  /// Rank 0 resolves the film into `img` and, with image.denoise, denoises it (the PNG
  /// shows the denoised RGB, the EXR gains denoised.R/G/B); a denoiser failure fails the
  /// render with TESSERA_ERROR_RENDER. Other ranks leave `img` empty.
  bool resolve_image(const Film& film, Image& img) {
    return phase(TESSERA_ERROR_RENDER, [&] {
      if (m_ctx.rank() != 0) return;
      img = film.resolve(m_spec.output.variance, m_spec.output.samples);
      if (!m_spec.image.denoise) return;
      const auto t0 = Clock::now();
      denoise(img);
      m_out.result.denoise_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    });
  }

  bool render_film(const PreparedScene& prepared, Film& film) {
    return phase(TESSERA_ERROR_RENDER, [&] {
      // With image.denoise every rank keeps the auxiliary sums: they travel with the pixels
      film = Film(m_spec.image.width, m_spec.image.height, m_spec.image.denoise);
      RenderStats stats;
      const auto t0 = Clock::now();
      try {
        m_ctx.render(prepared, film, stats);
      } catch (const DeadlineExceeded& e) {
        film = Film();  // the partial image is never resolved nor written
        time_limit_passed(e);
      }
      m_out.result.render_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
      m_out.result.stats.add_counters(stats);
      m_out.result.stats.wall_seconds += stats.wall_seconds;
      m_out.result.stats.threads = stats.threads;
    });
  }

  /// The render's annotations at this call's step and time (the colour bar of the scene's
  /// TF, range resolved), or none.
  std::optional<AnnotationDesc> annotations(const SceneDesc& scene) const {
    if (!m_spec.annotations) return std::nullopt;
    return config::build_annotations(*m_spec.annotations, m_spec.name, m_spec.field, scene.tf, m_call.step,
                                     m_call.time);
  }

  bool run_cinema(const SceneDesc& scene, const std::vector<CinemaView>& views) {
    const bool root = m_ctx.rank() == 0;
    const std::string dir = (std::filesystem::path(m_cfg.global.output_dir) / (m_spec.name + ".cdb")).string();
    if (root && !m_render.cinema) m_render.cinema = std::make_unique<CinemaDatabase>(dir);
    for (const CinemaView& view : views) {
      PreparedScene prepared;
      if (!phase(TESSERA_ERROR_RENDER, [&] {
            SceneDesc s = scene;
            s.camera = view.camera;
            prepared = prepare_scene(s);
          }))
        return false;
      Film film;
      if (!render_film(prepared, film)) return false;
      Image img;
      if (!resolve_image(film, img)) return false;
      if (!phase(TESSERA_ERROR_IO, [&] {
            if (!root) return;
            const std::string rel = cinema_file_base(m_spec, m_call.step, m_call.time, view);
            const std::size_t first = m_out.result.files.size();
            const std::optional<AnnotationDesc> notes = annotations(scene);
            write_image_files((std::filesystem::path(dir) / rel).string(), m_spec.output, img, m_out.result.files,
                              notes ? &*notes : nullptr);
            // FILE column: the file Cinema viewers show as it is (the PNG) when written, else
            // the first; write_image_files appended one file per format, in formats' order
            const std::vector<ImageFormat>& formats = m_spec.output.formats;
            std::string shown = m_out.result.files[first];
            for (std::size_t k = 0; k < formats.size(); ++k)
              if (image_format(formats[k]).shown_as_is) shown = m_out.result.files[first + k];
            m_render.cinema->set_row(m_call.time, view.phi, view.theta,
                                     std::filesystem::path(shown).lexically_relative(dir).string());
          }))
        return false;
    }
    return phase(TESSERA_ERROR_IO, [&] {
      if (root) m_render.cinema->write();
    });
  }

  /// A render the budget skipped: no work, no files; a warning on rank 0 naming the budget,
  /// logged the 1st, 2nd, 4th, 8th, ... time in a row (a budget far too small for a render
  /// that fires every step must not flood the log).
  PassOutcome skipped() {
    RenderResult& r = m_out.result;
    r.budget_skipped = true;
    r.simulation_seconds = m_call.simulation_seconds;
    const int n = ++m_render.budget_skips;
    if (m_ctx.rank() != 0) return std::move(m_out);
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "skipped: the render budget (tessera.budget = %g, rendering at most %gx the simulation's time) "
                  "cannot pay for image.min_spp = %d now (%.3g s in the account, the run at %.3gx so far)",
                  m_cfg.global.budget, m_cfg.global.budget, m_spec.min_spp,
                  m_call.budget ? m_call.budget->allowance() : 0.0, m_call.budget ? m_call.budget->ratio() : 0.0);
    r.warnings.emplace_back(buf);
    if ((n & (n - 1)) == 0)
      log_line("warning: render '" + r.name + "' at step " + std::to_string(r.step) + ": " + r.warnings.back() +
               (n > 1 ? " (" + std::to_string(n) + " calls in a row)" : std::string()));
    return std::move(m_out);
  }

  std::string summary() const {
    const RenderResult& r = m_out.result;
    char buf[256];
    std::snprintf(buf, sizeof buf, "render '%s' step %lld (t=%g): %dx%d, %d spp, %.3f s, %.3g samples/s",
                  r.name.c_str(), static_cast<long long>(r.step), r.time, m_spec.image.width, m_spec.image.height,
                  m_spp, r.render_seconds, r.samples_per_second);
    std::string line = buf;
    // The render budget: the plan, what a pixel got, the account the plan had to spend
    if (m_call.budget) {
      std::snprintf(
          buf, sizeof buf,
          " (budget %g: %d of %d spp planned, %.3g a pixel on average, %.3g s in the account, the run at %.3gx so far)",
          m_cfg.global.budget, m_spp, m_spec.image.spp, r.actual_spp, m_call.budget->allowance(),
          m_call.budget->ratio());
      line += buf;
    }
    if (m_spec.image.denoise) {
      std::snprintf(buf, sizeof buf, ", denoised in %.3f s", r.denoise_seconds);
      line += buf;
    }
    // The in situ cost: this render against the simulation's time it watched
    if (r.simulation_seconds > 0.0) {
      std::snprintf(buf, sizeof buf, ", %.3gx the simulation's %.3g s since the last render", r.cost_ratio,
                    r.simulation_seconds);
      line += buf;
    }
    if (m_spec.output.cinema) line += ", " + std::to_string(r.files.size()) + " files";
    else
      for (std::size_t i = 0; i < r.files.size(); ++i) line += (i ? ", " : " -> ") + r.files[i];
    return line;
  }

  ParallelContext& m_ctx;
  const config::Config& m_cfg;
  RenderState& m_render;
  const config::RenderSpec& m_spec;
  CallData& m_call;
  SummaryCache& m_summaries;
  FieldBinding m_binding;
  std::optional<AmrLayout> m_amr;  ///< refinement levels: every rank's boxes (empty: one level)
  FieldPlan m_plan;                ///< replicated or distributed, and the cache's size
  PagedField m_paged;              ///< distributed mode: this rank's block and the brick cache
  AmrVirtualLayout m_virtual;      ///< distributed mode with levels: the virtual grid of the patches
  std::string m_field_name;        ///< the simulation's name of the bound field
  PassOutcome m_out;
  Clock::time_point m_start;  ///< when this render began (its time limit counts from here)
  Clock::time_point m_deadline = Clock::time_point::max();  ///< tessera.time_limit; max = none
  int m_spp;  ///< samples per pixel: the budget's plan, image.spp without one; 0 = skipped
};

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
      return Pass(ctx, cfg, render, call, summaries).run(check_when, quiet);
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
