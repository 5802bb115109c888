// The scene and prepare phases of a render (prepare_phase.h).
#include "pass/prepare_phase.h"

#include "pass/device_phase.h"

#include <tessera/config/build_scene.h>
#include <tessera/cuda_render.h>
#include <tessera/field_summary.h>

#include <chrono>
#include <memory>

namespace tessera::insitu {

std::optional<SceneSetup> scene_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field,
                                      std::pair<double, double> range) {
  SceneSetup s;
  const FieldBinding& b = field.binding;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] {
        s.scene = config::build_scene(pass.spec, b.global_bounds, range, b.geometry, pass.call.step);
        s.scene.options = config::build_render_options(pass.spec, pass.cfg.global);
        s.scene.options.frame = static_cast<std::uint64_t>(pass.call.step);
        s.scene.options.deadline = pass.deadline;
        s.scene.image.spp = pass.spp;  // the render budget's plan (image.spp without one)
        set_device_options(pass, field, s.scene.options);
        if (pass.spec.output.cinema) s.views = cinema_views(*pass.spec.output.cinema, s.scene.camera, b.global_bounds);
      }))
    return std::nullopt;
  return s;
}

PreparedScene prepare_scene(const PassContext& pass, const BoundField& field, PlacedField& placed,
                            const SceneDesc& scene, RenderResult& result) {
  SummaryCache::Entry& entry = pass.summaries.entry(field.name);
  ParallelContext& ctx = pass.ctx;
  const CallData& call = pass.call;
  const auto t0 = PassClock::now();
  PreparedScene prepared;
  try {
    if (placed.plan.distributed && field.amr) {
      // Refinement levels, distributed: the summary from every rank's parts (collective,
      // unless one was kept), the other ranks' patches through the cache
      AmrField amr = field.amr->meta;
      amr.patches = call.assembled_patches;
      amr.cache = placed.paged.cache;
      amr.layout = placed.virtual_layout;
      FieldView level0;
      level0.dtype = amr.dtype;
      for (int a = 0; a < 3; ++a) level0.dims[a] = amr.dims[a];
      const int edge = majorant_edge(level0, scene.integrator);
      std::shared_ptr<const FieldSummary> summary = entry.find(edge);
      if (!summary) {
        FieldSummary::Parts parts = amr_summary_parts(amr, field.amr->assoc, edge);
        ctx.reduce_parts(parts);
        FieldLayout layout;
        layout.dtype = amr.dtype;
        for (int a = 0; a < 3; ++a) layout.dims[a] = amr.dims[a];
        summary = FieldSummary::from_parts(std::move(parts), layout, edge);
      }
      ctx.serve_while([&] { prepared = prepare(amr, scene, summary); });
    } else if (placed.plan.distributed) {
      // The global summary (made by prepare_phase, in a gate of its own); the adaptive
      // preview in prepare reads the field, so it runs while the ranks serve bricks
      ctx.serve_while([&] { prepared = prepare(placed.paged, scene, placed.summary); });
    } else if (field.amr) {
      // Refinement levels: the hierarchy, its summary (amr_summary) at level 0's edge
      AmrField amr = field.amr->meta;
      amr.patches = call.assembled_patches;
      FieldView level0;
      level0.dtype = amr.dtype;
      for (int a = 0; a < 3; ++a) level0.dims[a] = amr.dims[a];
      prepared = prepare(amr, scene, entry.find(majorant_edge(level0, scene.integrator)));
    } else if (field.magnitude) {
      // A vector's magnitude read in place: its summary (range phase) at the scene's edge
      const FieldView& first = field.magnitude->components[0];
      prepared = prepare(*field.magnitude, scene, entry.find(majorant_edge(first, scene.integrator)));
    } else if (field.device.in_place || field.device.assemble_on_device) {
      // Device memory read in place (the simulation's array, or one rank's device blocks
      // assembled on the device): its summary made on the GPU, so that prepare never reads it;
      // a kept summary of another array (a replica assembled again) is made anew
      const int edge = majorant_edge(call.assembled, scene.integrator);
      std::shared_ptr<const FieldSummary> summary = entry.find(edge);
      if (!summary || !summary->matches(call.assembled, edge)) {
        summary = cuda_field_summary(call.assembled, edge, call.cuda_stream);
        ++result.field_passes;
        entry.keep(summary);
      }
      prepared = prepare(call.assembled, scene, summary);
    } else {
      prepared = prepare(call.assembled, scene, entry.find(majorant_edge(call.assembled, scene.integrator)));
    }
  } catch (const DeadlineExceeded& e) {  // the adaptive preview ran past the time limit
    time_limit_passed(pass, e);
  }
  result.prepare_seconds += std::chrono::duration<double>(PassClock::now() - t0).count();
  if (!prepared.summary_reused()) {
    ++result.field_passes;
    entry.keep(prepared.summary());
  }
  return prepared;
}

std::optional<PreparedScene> prepare_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field,
                                           PlacedField& placed, const SceneDesc& scene, RenderResult& result) {
  if (placed.plan.distributed && !field.amr) {
    // The global summary from every rank's blocks (collective), unless one was kept, in a
    // gate of its own: a rank whose blocks cannot be summarised (a device block's copy
    // failing) fails every rank here, before the prepare whose serving all ranks must join
    const auto t0 = PassClock::now();  // counted in prepare_seconds, as prepare's own summaries are
    if (!gate.run(TESSERA_ERROR_RENDER, [&] {
          const FieldBinding& b = field.binding;
          FieldView global = b.local;
          for (int a = 0; a < 3; ++a) global.dims[a] = b.placement.global_dims[a];
          const int edge = majorant_edge(global, scene.integrator);
          placed.summary = pass.summaries.entry(field.name).find(edge);
          if (!placed.summary)
            placed.summary = pass.ctx.summarize_blocks(b.blocks, b.placement.global_dims, b.local.dtype, edge);
        }))
      return std::nullopt;
    result.prepare_seconds += std::chrono::duration<double>(PassClock::now() - t0).count();
  }
  PreparedScene prepared;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] { prepared = prepare_scene(pass, field, placed, scene, result); }))
    return std::nullopt;
  return prepared;
}

}  // namespace tessera::insitu
