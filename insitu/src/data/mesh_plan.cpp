// The memory plan of a mesh render (mesh_plan.h).
#include "data/mesh_plan.h"

#include <tessera/config/build_scene.h>
#include <tessera/config/render_memory.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tessera::insitu {

FieldPlan plan_mesh(const config::Config& cfg, const config::RenderSpec& spec, int ranks, int ranks_on_node, bool root,
                    std::uint64_t cells, std::uint64_t received) {
  if (cfg.global.distribution == config::Distribution::Distributed && ranks > 1)
    throw std::runtime_error("distribution: distributed is not supported yet for curvilinear and unstructured "
                             "meshes (every rank receives the whole mesh): use replicated or auto");
  const int node_ranks = std::max(1, ranks_on_node);
  // The grid laid over the mesh has about one sample per cell: its dims for the footprint
  FieldView grid;
  const auto edge =
      static_cast<std::int64_t>(std::ceil(std::cbrt(static_cast<double>(std::max<std::uint64_t>(cells, 1))))) + 1;
  for (std::int64_t& d : grid.dims) d = edge;
  RenderFootprint f = config::render_footprint(spec, config::build_render_options(spec, cfg.global),
                                               spec.output.formats, grid, node_ranks);
  f.writes = root;
  f.keeps_last_image = root;
  FieldPlan plan;
  plan.base = estimate_render_memory(f);
  plan.threads = f.threads;
  const config::MemoryLimit limit = config::memory_limit(cfg.global, node_ranks);
  plan.limit = limit.bytes;
  plan.limit_text = limit.text;
  MemoryEstimate e = plan.base;
  const std::uint64_t max = std::numeric_limits<std::uint64_t>::max();
  e.add("mesh lookup tables", cells > max / kMeshTableBytesPerCell ? max : cells * kMeshTableBytesPerCell);
  e.add("the other ranks' mesh domains", received);
  if (e.total() > plan.limit)
    throw std::runtime_error("needs an estimated " + e.describe() + " on this rank, more than " + plan.limit_text);
  return plan;
}

}  // namespace tessera::insitu
