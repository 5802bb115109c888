// The range phase of a render (range_phase.h).
#include "pass/range_phase.h"

#include "data/block_ops.h"

#include <tessera/cuda_render.h>
#include <tessera/field_summary.h>

#include <exception>
#include <limits>
#include <memory>

namespace tessera::insitu {
namespace {

/// Global finite min/max of a field: this rank's finite values (all its blocks), then
/// ParallelContext::range. A rank without finite values contributes nothing; with none
/// anywhere, lo > hi.
std::pair<double, double> global_range(ParallelContext& ctx, std::span<const FieldBlock> blocks) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // A rank whose blocks cannot be read (a device block's copy failing) still takes part in
  // the reduction, then fails: the phase's gate agrees on the failure, no rank is left
  // waiting in the collective
  std::pair<double, double> local{kInf, -kInf};
  std::exception_ptr error;
  try {
    local = blocks_range(blocks).value_or(local);
  } catch (...) {
    error = std::current_exception();
  }
  const std::pair<double, double> global = ctx.range(local.first, local.second);
  if (error) std::rethrow_exception(error);
  return global;
}

std::pair<double, double> cached_range(const PassContext& pass, const BoundField& field, RenderResult& result) {
  const std::string key = pass.spec.field_key();
  for (const auto& [k, range] : pass.call.ranges)
    if (k == key) return range;
  // From a summary of the global field: one kept from the last call (agreed by all ranks,
  // so all skip the reduction alike), or on one rank, where the global field is this
  // rank's view, the one this call made or makes now for prepare; else a pass here
  SummaryCache::Entry& entry = pass.summaries.entry(field.name);
  // (One rank with several domains, or levels: no summary of the whole field before the
  // replica; whole() is false with levels)
  const FieldBinding& b = field.binding;
  const bool whole = pass.ctx.size() == 1 && b.whole();
  std::shared_ptr<const FieldSummary> s = entry.kept || whole ? entry.find(0) : nullptr;
  if (!s && whole) {
    const int edge = majorant_edge(b.local, pass.spec.integrator.desc);
    s = field.magnitude         ? magnitude_summary(*field.magnitude, edge)
        : field.device.in_place ? cuda_field_summary(b.local, edge, pass.call.cuda_stream)
                                : FieldSummary::build(b.local, edge);
    ++result.field_passes;
    entry.keep(s);
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const auto range = !s                ? global_range(pass.ctx, b.blocks)
                     : s->has_finite() ? std::pair{s->value_min(), s->value_max()}
                                       : std::pair{kInf, -kInf};
  pass.call.ranges.emplace_back(key, range);
  return range;
}

}  // namespace

void agree_on_kept_summaries(const PassContext& pass, const BoundField& field) {
  SummaryCache::Entry& entry = pass.summaries.entry(field.name);
  if (entry.decided) return;
  const SummaryKey key = SummaryKey::of(field.binding);
  const bool keep = pass.ctx.agree(entry.carried && !entry.summaries.empty() && entry.key == key);
  if (!keep) entry.summaries.clear();
  entry.kept = keep;
  entry.key = key;
  entry.decided = true;
}

std::optional<std::pair<double, double>> range_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field,
                                                     RenderResult& result) {
  std::pair<double, double> range{0.0, 0.0};
  if (!gate.run(TESSERA_ERROR_RENDER, [&] { range = cached_range(pass, field, result); })) return std::nullopt;
  return range;
}

}  // namespace tessera::insitu
