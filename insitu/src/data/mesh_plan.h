#pragma once
/// The memory plan of a render over a curvilinear or unstructured mesh, checked before
/// anything is allocated: the render's own allocations, the mesh's lookup tables (at most
/// kMeshTableBytesPerCell per cell, mesh/mesh_tables.h) and, on several ranks, every rank's
/// domains received (replicated: each rank holds the whole mesh). Distributed mode is refused
/// for these meshes (not yet).
#include "data/field_plan.h"

#include <tessera/config/config.h>

#include <cstdint>

namespace tessera::insitu {

/// The bound on the core's tables per cell: its box (48 bytes), reference (16), value range
/// (16), location cell head (8) and at most 64 list entries (4 each), plus sorting's scratch.
inline constexpr std::uint64_t kMeshTableBytesPerCell = 400;

/// The plan (never distributed). `cells`: every rank's cells; `received`: the bytes of the
/// other ranks' domains this rank receives (0 on one rank). Throws std::runtime_error naming
/// the estimate and the limit when it does not fit, or for `distribution: distributed`.
FieldPlan plan_mesh(const config::Config& cfg, const config::RenderSpec& spec, int ranks, int ranks_on_node, bool root,
                    std::uint64_t cells, std::uint64_t received);

}  // namespace tessera::insitu
