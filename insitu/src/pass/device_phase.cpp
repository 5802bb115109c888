// The device phase of a render (device_phase.h).
#include "pass/device_phase.h"

#include "data/device_arrays.h"

#include <tessera/config/render_memory.h>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>

namespace tessera::insitu {
namespace {

/// What the render asks for that the GPU does not cover yet ("" when nothing): refinement
/// levels in a build without their kernel (-DTESSERA_CUDA_AMR=OFF), and refinement levels that
/// may be rendered distributed (several ranks, tessera.distribution not `replicated`): the GPU
/// has no distributed kernel for them. Decided before the plan, from the config alone, so that
/// every rank gives the same answer.
std::string gpu_gap([[maybe_unused]] const PassContext& pass, [[maybe_unused]] const BoundField& field) {
  if (!field.amr) return {};
#if defined(TESSERA_CUDA_AMR)
  if (pass.ctx.size() > 1 && pass.cfg.global.distribution != config::Distribution::Replicated)
    return "refinement levels on several ranks without tessera.distribution: replicated";
  return {};
#else
  return "refinement levels";
#endif
}

/// This rank's device from `tessera.device` for data that is (or is not) GPU memory, with
/// `gap` naming what the GPU does not cover ("" when nothing): `cuda` then throws, `auto`
/// takes the CPU.
config::DeviceSelection select_device(const PassContext& pass, bool gpu_readable, const std::string& gap) {
  const config::GlobalOptions& g = pass.cfg.global;
  const config::DeviceSelection sel = config::resolve_device(g, gpu_readable, pass.ctx.rank_on_node());
  if (sel.device == Device::Cuda && !gap.empty()) {
    if (g.device == config::DeviceChoice::Cuda)
      throw std::runtime_error("tessera.device is cuda, but " + gap + " is not supported on the GPU yet");
    return config::DeviceSelection{};
  }
  return sel;
}

/// One device kind on every rank: the GPU's sums differ from the CPU's by rounding, so a
/// render with tiles on both would depend on which rank drew which tile. With `auto`, a rank
/// that stays on the CPU (no GPU, or no device memory to read) keeps every rank there; with
/// `cuda` every rank is on the GPU or the gate before this failed them all. Collective.
void agree_device_kind(const PassContext& pass, config::DeviceSelection& sel) {
  if (pass.ctx.size() > 1 && pass.ctx.any(sel.device == Device::Cpu)) sel = config::DeviceSelection{};
}

}  // namespace

bool device_phase(PhaseGate& gate, const PassContext& pass, BoundField& field) {
  BlocksMemory where;  // asked once: the blocks do not change between the two gates
  const bool chosen = gate.run(TESSERA_ERROR_RENDER, [&] {
    where = blocks_memory(field.binding.blocks);
    // auto with a gap: the CPU, the field staged below
    field.device.selection = select_device(pass, where.gpu_readable, gpu_gap(pass, field));
  });
  if (!chosen) return false;
  agree_device_kind(pass, field.device.selection);
  return gate.run(TESSERA_ERROR_RENDER, [&] {
    FieldBinding& b = field.binding;
    const config::DeviceSelection& sel = field.device.selection;
    // A plain (single-level, scalar) field rendered on the GPU; staged magnitudes are host
    // memory already. In place: one rank holding it whole
    const bool plain = sel.device == Device::Cuda && !field.amr && !field.magnitude && field.staged.empty();
    field.device.in_place = plain && pass.ctx.size() == 1 && b.whole() && where.gpu_readable;
    if (field.device.in_place || !where.on_device()) return;
    // One rank, several blocks, some in device memory: assembled on the device (the host
    // blocks copied to their places), not staged
    field.device.assemble_on_device = plain && pass.ctx.size() == 1;
    // Several ranks on the GPU over a plain field: a distributed render reads the device
    // blocks where they are (summaries, other ranks' bricks and the cache's fills copied from
    // the device as they are asked for), so the staging waits for the plan
    field.device.deferred = plain && pass.ctx.size() > 1;
    if (field.device.assemble_on_device || field.device.deferred) {
      field.device.where = where;
      for (std::size_t i = 0; i < b.blocks.size(); ++i) {
        b.blocks[i].on_device = where.device[i] != 0;
        b.blocks[i].cuda_stream = pass.call.cuda_stream;
      }
      return;
    }
    const config::MemoryLimit limit = config::memory_limit(pass.cfg.global, std::max(1, pass.ctx.ranks_on_node()));
    stage_blocks_to_host(b, where, field.device.staging, pass.call.cuda_stream, limit.bytes, limit.text);
  });
}

bool stage_deferred(PhaseGate& gate, const PassContext& pass, BoundField& field, RenderResult& result) {
  // Only ranks on the GPU defer, and the ranks agreed on one device kind: every rank of such
  // a render takes part in the gate, whether it deferred or not
  if (field.device.selection.device != Device::Cuda || pass.ctx.size() == 1) return true;
  const std::uint64_t before = field.device.staging.bytes;
  const bool staged = gate.run(TESSERA_ERROR_RENDER, [&] {
    if (!field.device.deferred) return;
    field.device.deferred = false;
    FieldBinding& b = field.binding;
    for (FieldBlock& blk : b.blocks) blk.on_device = false;
    const config::MemoryLimit limit = config::memory_limit(pass.cfg.global, std::max(1, pass.ctx.ranks_on_node()));
    stage_blocks_to_host(b, field.device.where, field.device.staging, pass.call.cuda_stream, limit.bytes, limit.text);
  });
  result.stats.bytes_to_host += field.device.staging.bytes - before;
  return staged;
}

std::optional<config::DeviceSelection> mesh_device_phase(PhaseGate& gate, const PassContext& pass, bool gpu_readable) {
  config::DeviceSelection sel;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] { sel = select_device(pass, gpu_readable, {}); })) return std::nullopt;
  agree_device_kind(pass, sel);
  return sel;
}

void set_device_options(const PassContext& pass, const BoundField& field, RenderOptions& options) {
  set_device_options(pass, field.device.selection, options);
  // A replica assembled on the device is Tessera's memory too: the render gets what is left
  // (at least one byte: 0 would mean no limit)
  if (field.device.assemble_on_device && pass.call.assembled_device) {
    const FieldView& r = pass.call.assembled;
    const std::uint64_t replica = static_cast<std::uint64_t>(r.vertex_count()) * dtype_size(r.dtype);
    options.device_memory_limit = options.device_memory_limit > replica ? options.device_memory_limit - replica : 1;
  }
}

void set_device_options(const PassContext& pass, const config::DeviceSelection& sel, RenderOptions& options) {
  options.device = sel.device;
  options.cuda_device = sel.cuda_device;
  options.cuda_stream = pass.call.cuda_stream;
  options.device_memory_limit = config::memory_limit(pass.cfg.global, std::max(1, pass.ctx.ranks_on_node())).bytes;
}

}  // namespace tessera::insitu
