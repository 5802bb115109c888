// FieldPlan: replicated or distributed, the cache's size, and the memory check (field_plan.h).
#include "data/field_plan.h"

#include "data/amr_layout.h"

#include <tessera/brick_cache.h>
#include <tessera/config/build_scene.h>
#include <tessera/config/render_memory.h>
#include <tessera/memory_estimate.h>
#include <tessera/number_text.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace tessera::insitu {
namespace {

std::uint64_t field_bytes(const FieldBinding& b) {
  std::uint64_t vertices = 1;
  for (int a = 0; a < 3; ++a)
    vertices *= static_cast<std::uint64_t>(std::max<std::int64_t>(1, b.placement.global_dims[a]));
  return vertices * dtype_size(b.local.dtype);
}

[[noreturn]] void over_limit(const MemoryEstimate& e, const FieldPlan& plan) {
  throw std::runtime_error("needs an estimated " + e.describe() + " on this rank, more than " + plan.limit_text);
}

}  // namespace

int brick_shift(const std::int64_t global_dims[3]) {
  const std::int64_t longest = std::max({global_dims[0], global_dims[1], global_dims[2]});
  int shift = 3;
  while (shift < kMaxBrickShift && (std::int64_t{1} << (shift + 1)) <= longest / 8) ++shift;
  return shift;
}

FieldPlan plan_field(const config::Config& cfg, const config::RenderSpec& spec, const FieldBinding& binding, int ranks,
                     int ranks_on_node, bool root, const AmrLayout* amr, bool gpu) {
  const int node_ranks = std::max(1, ranks_on_node);
  FieldView global;  // dims only: what the footprint reads (and which axes are rectilinear)
  for (int a = 0; a < 3; ++a) global.dims[a] = binding.placement.global_dims[a];
  RenderFootprint f = config::render_footprint(spec, config::build_render_options(spec, cfg.global),
                                               spec.output.formats, global, node_ranks, binding.geometry);
  // What the adapter adds: rank 0 writes every image and keeps the last one; the Cinema views
  f.writes = root;
  f.keeps_last_image = root;
  f.gpu = gpu;
  if (spec.output.cinema)
    f.views = static_cast<int>(spec.output.cinema->azimuths.size() * spec.output.cinema->elevations.size());

  FieldPlan plan;
  plan.base = estimate_render_memory(f);
  if (binding.staged_bytes > 0) plan.base.add("vector magnitude (this rank's blocks, staged)", binding.staged_bytes);
  plan.threads = f.threads;
  plan.gpu = gpu;
  config::MemoryLimit limit = config::memory_limit(cfg.global, node_ranks);
  plan.limit = limit.bytes;
  plan.limit_text = std::move(limit.text);
  plan.cache_fraction = cfg.global.brick_cache;
  plan.macrocell_edge = f.macrocell_edge;
  // One rank reads a field held whole in place; several domains on one rank get a replica
  // (refinement levels: one rank reads every patch in place; several share a node replica
  // of every patch)
  const bool replica = amr ? ranks > 1 : ranks > 1 || (binding.domains && !binding.whole());
  if (replica)
    plan.replica_share = (amr ? amr->patch_bytes() : field_bytes(binding)) / static_cast<std::uint64_t>(node_ranks);
  switch (cfg.global.distribution) {
    case config::Distribution::Replicated: plan.distributed = false; break;
    case config::Distribution::Distributed: plan.distributed = ranks > 1; break;
    case config::Distribution::Auto: plan.distributed = ranks > 1 && plan.replica_share > plan.limit / 2; break;
  }
  if (!plan.distributed) {
    MemoryEstimate e = plan.base;
    const char* what = amr ? "refinement levels' replica" : "field replica";
    if (ranks > 1) e.add(std::string(what) + " (this rank's share of its node's)", plan.replica_share);
    else if (replica) e.add(std::string(what) + " (the domains' copy)", plan.replica_share);
    if (amr) e.add("refinement level tables", amr->table_bytes(plan.macrocell_edge));
    if (e.total() > plan.limit) over_limit(e, plan);
  }
  return plan;
}

void plan_distributed(FieldPlan& plan, const FieldBinding& binding, int shift, const AmrLayout* amr) {
  plan.distributed = true;
  // Refinement levels: the virtual grid of every level's patches (amr_layout.h)
  const AmrVirtualLayout virtual_grid = amr ? amr->virtual_grid() : AmrVirtualLayout{};
  const std::int64_t* dims = amr ? virtual_grid.dims : binding.placement.global_dims;
  const DType dtype = amr ? amr->meta.dtype : binding.local.dtype;
  const std::uint64_t bytes = amr ? amr->patch_bytes() : field_bytes(binding);
  MemoryEstimate base = plan.base;
  if (amr) base.add("refinement level tables", amr->table_bytes(plan.macrocell_edge));
  // The cache's cap: tessera.brick_cache's share of the field, but at least one brick (a
  // one-slot cache still makes progress: only the memory limit can make a distributed render
  // impossible); at 1, every brick of the cut, its padding at the far faces included
  const auto cap_for = [&](const BrickGrid& g) {
    const std::uint64_t all = static_cast<std::uint64_t>(g.brick_count()) * g.slot_bytes();
    if (plan.cache_fraction >= 1.0) return all;
    return std::max<std::uint64_t>(g.slot_bytes(),
                                   static_cast<std::uint64_t>(plan.cache_fraction * static_cast<double>(bytes)));
  };
  // Bricks: about an eighth of the longest axis (small bricks waste little of a cache that must
  // evict); but when the cap and the limit let the cache keep every brick of a coarser cut,
  // nothing is ever evicted and fewer, larger messages win: the coarsest such cut
  plan.shift = shift > 0 ? shift : brick_shift(dims);
  for (int s = kMaxBrickShift; shift <= 0 && s > plan.shift; --s) {
    const BrickGrid g = BrickGrid::make(dims, dtype, s);
    const std::uint64_t all = static_cast<std::uint64_t>(g.brick_count()) * g.slot_bytes();
    if (all <= cap_for(g) &&
        base.total() + BrickCache::bytes_for(g, static_cast<std::size_t>(g.brick_count())) <= plan.limit) {
      plan.shift = s;
      break;
    }
  }
  const BrickGrid grid = BrickGrid::make(dims, dtype, plan.shift);
  const std::uint64_t slot = grid.slot_bytes();
  MemoryEstimate e = base;
  e.add("brick directory", BrickCache::bytes_for(grid, 0));
  if (plan.gpu) {
    // The device's pool, kept on the host: per brick of the cut, and a slot to fill
    e.add("the GPU's brick bookkeeping",
          kGpuHostBytesPerBrick * static_cast<std::uint64_t>(grid.brick_count()) + grid.slot_bytes());
  }
  const std::uint64_t used = e.total();
  const std::uint64_t budget = used < plan.limit ? std::min(plan.limit - used, cap_for(grid)) : 0;
  plan.capacity =
      static_cast<std::size_t>(std::min<std::uint64_t>(budget / slot, static_cast<std::uint64_t>(grid.brick_count())));
  if (plan.capacity < 1) {
    e.add("brick cache (one brick)", slot);
    over_limit(e, plan);
  }
  e.add("brick cache", plan.capacity * slot);
  plan.cache_warning = small_cache_warning(grid, plan.capacity, plan.threads, plan.cache_fraction);
}

std::string small_cache_warning(const BrickGrid& grid, std::size_t capacity, int threads, double fraction) {
  const std::int64_t crossing = grid.bricks[0] + grid.bricks[1] + grid.bricks[2];
  const std::int64_t useful = kCacheSlotsPerCrossing * std::max(1, threads) * crossing;
  const auto slots = static_cast<std::int64_t>(std::min<std::size_t>(capacity, INT64_MAX));
  if (slots >= grid.brick_count() || slots >= useful) return "";
  const std::string fraction_text = short_number(fraction);
  return "distributed mode: the brick cache holds " + std::to_string(slots) + " of the field's " +
         std::to_string(grid.brick_count()) + " bricks (" + std::to_string(grid.edge()) +
         "^3 vertices), fewer than the " + std::to_string(useful) + " (" + std::to_string(kCacheSlotsPerCrossing) +
         " x " + std::to_string(std::max(1, threads)) + " thread(s) x " + std::to_string(crossing) +
         " bricks along x + y + z) that the paths being traced can cross: bricks are fetched again and "
         "again and the render can be tens to hundreds of times slower than replicated; raise "
         "tessera.brick_cache (now " +
         fraction_text +
         ") or tessera.memory_limit_mb, or use "
         "distribution: replicated";
}

std::string describe_plan(const FieldPlan& plan, config::Distribution asked) {
  const char* how = asked == config::Distribution::Auto          ? "auto"
                    : asked == config::Distribution::Distributed ? "distributed"
                                                                 : "replicated";
  std::string line = std::string("distribution ") + how + " -> " + (plan.distributed ? "distributed" : "replicated");
  if (asked == config::Distribution::Auto)
    line +=
        " (replica share " + format_bytes(plan.replica_share) + " per rank against half of " + plan.limit_text + ")";
  if (plan.distributed) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "; bricks of %d^3 vertices, cache of %zu bricks", 1 << plan.shift, plan.capacity);
    line += buf;
  }
  return line;
}

}  // namespace tessera::insitu
