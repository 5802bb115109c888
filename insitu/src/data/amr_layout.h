#pragma once
/// Refinement levels in the adapter (amr.h): every rank's boxes checked as one hierarchy, and
/// the hierarchy's patches as the renderer reads them in replicated mode: one rank's own
/// arrays in place, or a replica of every rank's patches (parallel_context.h assemble_amr).
///
/// Order: the boxes of all ranks in (rank, domain) order, each rank's blocks sorted by their
/// domain index (in_domain_order); the replica concatenates the patches in that order, each
/// dense C order (i fastest). Every rank builds the same list, so the patch list is the same
/// on every rank up to memory addresses (the image does not depend on the order anyway).
#include "data/block_layout.h"
#include "data/field_binding.h"

#include <tessera/amr.h>
#include <tessera/scene.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace tessera::insitu {

/// Every rank's boxes of a hierarchy, checked.
struct AmrLayout {
  /// dtype, level-0 dims, nlevels, ratios and names ("rank R domain D", one per box); no
  /// patches (the views live where assemble_amr puts them).
  AmrField meta;
  Association assoc = Association::Vertex;
  std::vector<BlockRecord> boxes;  ///< every rank's blocks, (rank, domain) order
  std::vector<int> counts;         ///< blocks per rank (boxes of rank r follow those of r - 1)

  /// Bytes of every box's elements (what a node's replica holds).
  std::uint64_t patch_bytes() const;
  /// Byte offset of box n in the replica (the boxes before it, packed).
  std::vector<std::uint64_t> replica_offsets() const;
  /// Bytes prepare() allocates for the level tables at macrocell edge `edge` (amr_table_bytes,
  /// over the boxes alone).
  std::uint64_t table_bytes(int edge) const;
  /// Distributed mode: the virtual grid every rank pages the others' patches through
  /// (amr_virtual_layout, levels aligned to the largest brick edge, so any brick cut fits).
  AmrVirtualLayout virtual_grid() const;
};

/// The hierarchy a binding describes (dtype, level-0 dims, nlevels, ratios), no patches.
AmrField amr_meta(const FieldBinding& binding, DType dtype);

/// This rank's blocks sorted by domain index (their order in the layout).
std::vector<FieldBlock> in_domain_order(std::span<const FieldBlock> blocks);

/// The records of this rank's blocks (already in domain order), at `rank`.
std::vector<BlockRecord> block_records(std::span<const FieldBlock> ordered, int rank);

/// Checks every rank's boxes (`boxes` in (rank, domain) order, `counts` per rank) as one
/// hierarchy of `meta` (check_amr_boxes: levels, extents, overlap within a level, level 0
/// covering the mesh, each level inside the one below), named "rank R domain D". Throws
/// LayoutError with core's message; alike on every rank, which all pass the same boxes.
AmrLayout check_amr_layout(std::vector<BlockRecord> boxes, std::vector<int> counts, const AmrField& meta,
                           Association assoc);

/// One rank's amr_layout (parallel_context.h): its blocks' views validated, then checked.
AmrLayout amr_layout_one_rank(std::span<const FieldBlock> blocks, const AmrField& meta, Association assoc);

/// One rank: the patches are its own blocks' views, in place (zero copy). `ordered`: its
/// blocks in domain order (the layout's).
std::vector<AmrPatch> patches_in_place(std::span<const FieldBlock> ordered, const AmrLayout& layout);

/// Distributed mode: every box of the layout as a patch; this rank's (`ordered`: its blocks in
/// domain order, at `rank`) read in place, the others' with no data (read through the cache).
std::vector<AmrPatch> patches_distributed(std::span<const FieldBlock> ordered, const AmrLayout& layout, int rank);

/// Distributed mode: this rank's blocks (`ordered`) placed in the virtual grid `v` (level l's
/// element s at v.base[l] + s), and every rank's boxes likewise, with their owners.
std::vector<FieldBlock> virtual_blocks(std::span<const FieldBlock> ordered, const AmrVirtualLayout& v);
std::vector<BlockRecord> virtual_records(const AmrLayout& layout, const AmrVirtualLayout& v);

/// Several ranks: the patches in a replica at `base` laid out as replica_offsets() says.
std::vector<AmrPatch> patches_in_replica(const void* base, const AmrLayout& layout);

}  // namespace tessera::insitu
