// The plan and assemble phases of a render (placement_phase.h).
#include "pass/placement_phase.h"

#include "data/amr_layout.h"
#include "data/block_ops.h"
#include "outputs/error_policy.h"

#include <tessera/config/render_memory.h>
#include <tessera/cuda_memory.h>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace tessera::insitu {

std::optional<FieldPlan> plan_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field, bool quiet) {
  ParallelContext& ctx = pass.ctx;
  const AmrLayout* amr = field.amr ? &*field.amr : nullptr;
  FieldPlan plan;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] {
        plan = plan_field(pass.cfg, pass.spec, field.binding, ctx.size(), ctx.ranks_on_node(), pass.root(), amr,
                          field.device.selection.device == Device::Cuda);
      }))
    return std::nullopt;
  if (pass.cfg.global.distribution == config::Distribution::Auto && ctx.size() > 1)
    plan.distributed = ctx.any(plan.distributed);
  // (the same answer on every rank: the config is the same and `auto` stays replicated)
  if (plan.distributed) {
    if (!gate.run(TESSERA_ERROR_RENDER, [&] { plan_distributed(plan, field.binding, 0, amr); })) return std::nullopt;
    // One brick cut for all: the finest any rank chose (their limits may differ). Every rank
    // takes part in the phase (it ends in a collective), re-planning only where it differs
    const int agreed = ctx.min(plan.shift);
    if (!gate.run(TESSERA_ERROR_RENDER, [&] {
          if (agreed != plan.shift) plan_distributed(plan, field.binding, agreed, amr);
        }))
      return std::nullopt;
  }
  RenderState& render = pass.render;
  if (pass.root() && ctx.size() > 1 && render.logged_mode != (plan.distributed ? 1 : 0)) {
    render.logged_mode = plan.distributed ? 1 : 0;
    if (!quiet) log_line("render '" + pass.spec.name + "': " + describe_plan(plan, pass.cfg.global.distribution));
  }
  return plan;
}

std::optional<PlacedField> assemble_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field,
                                          FieldPlan plan) {
  ParallelContext& ctx = pass.ctx;
  CallData& call = pass.call;
  const FieldBinding& b = field.binding;
  PlacedField placed;
  placed.plan = std::move(plan);
  const std::string key = pass.spec.field_key();
  if (!gate.run(TESSERA_ERROR_RENDER, [&] {
        if (placed.plan.distributed && field.amr) {
          // Refinement levels: every rank's patches paged through one virtual grid
          call.assembled_key.reset();
          const AmrVirtualLayout v = field.amr->virtual_grid();
          const std::vector<FieldBlock> ordered = in_domain_order(b.blocks);
          call.assembled_patches = patches_distributed(ordered, *field.amr, ctx.rank());
          placed.paged = ctx.distribute_amr(virtual_blocks(ordered, v), virtual_records(*field.amr, v), v.dims,
                                            field.amr->meta.dtype, placed.plan.shift, placed.plan.capacity);
          placed.virtual_layout = v;
        } else if (placed.plan.distributed) {
          call.assembled_key.reset();  // distribute() frees the replica
          placed.paged = ctx.distribute_blocks(b.blocks, b.placement.global_dims, b.local.dtype, placed.plan.shift,
                                               placed.plan.capacity);
          // A GPU render reads the own block where the simulation keeps it (left there on
          // several ranks' GPUs, FieldBlock::on_device; else a staged copy serves the host
          // side: checks, other ranks' requests)
          if (!placed.paged.local_device_only)
            placed.paged.local_device = field.device.staging.device_original(placed.paged.local.data);
        } else if (field.amr) {
          if (call.assembled_key != key) {
            call.assembled_key.reset();
            call.assembled_patches = ctx.assemble_amr(b.blocks, *field.amr);
            call.assembled_key = key;
          }
        } else if (field.magnitude) {
          // A vector's magnitude on one rank holding the grid whole: read in place
        } else if (call.assembled_key != key) {
          call.assembled_key.reset();
          call.assembled_device.reset();
          if (field.device.assemble_on_device) {
            // One rank's blocks, some on the device: checked as the host's assembly checks
            // them, then placed into one array on that device (nothing copied to the host;
            // the host blocks' elements copied over)
            check_blocks_one_rank(b.blocks, b.placement.global_dims);
            std::vector<FieldView> views;
            std::vector<std::array<std::int64_t, 3>> offsets;
            for (const FieldBlock& blk : b.blocks) {
              views.push_back(blk.view);
              offsets.push_back({blk.offset[0], blk.offset[1], blk.offset[2]});
            }
            const config::MemoryLimit limit = config::memory_limit(pass.cfg.global, 1);
            DeviceReplica r = cuda_assemble_on_device(views, offsets, b.placement.global_dims, b.local.dtype,
                                                      call.cuda_stream, limit.bytes, limit.text);
            call.assembled = r.view;
            call.assembled_device = std::move(r.memory);
            placed.assembled_to_device = r.bytes_to_device;
          } else {
            call.assembled = ctx.assemble_blocks(b.blocks, b.placement.global_dims, b.local.dtype);
          }
          call.assembled_key = key;
        }
      }))
    return std::nullopt;
  return placed;
}

}  // namespace tessera::insitu
