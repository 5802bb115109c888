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

/// The bound on the core's tables per cell at their peak (mesh/mesh_tables.cpp): its box (48
/// bytes), reference (16) and macrocell span (24, mesh/macro_spans.h), with either the sort's
/// scratch (112) or the
/// location lists (at most 64 entries of 4 bytes, and two heads of 8 bytes for each of at most
/// 4 location cells per cell): 88 + max(112, 320) = 408, rounded up.
inline constexpr std::uint64_t kMeshTableBytesPerCell = 480;

/// The plan (never distributed). `cells`: every rank's cells; `received`: the bytes of the
/// other ranks' domains this rank receives (0 on one rank). Throws std::runtime_error naming
/// the estimate and the limit when it does not fit, or for `distribution: distributed`.
FieldPlan plan_mesh(const config::Config& cfg, const config::RenderSpec& spec, int ranks, int ranks_on_node, bool root,
                    std::uint64_t cells, std::uint64_t received);

}  // namespace tessera::insitu
