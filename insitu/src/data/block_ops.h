#pragma once
/// What the contexts do with a rank's blocks (parallel_context.h) on the rank itself: copy a
/// block into a dense C-order array (a replica, a brick's slot) and combine the partial field
/// summaries of its blocks.
#include "data/field_block.h"

#include <tessera/field_summary.h>
#include <tessera/field_view.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace tessera::insitu {

/// Copies strided view `v` into the box at `offset` of the dense C-order array (i fastest) of
/// `dims` elements of v's dtype at `dst`: one copy, no staging buffer.
void copy_block(const FieldView& v, void* dst, const std::int64_t dims[3], const std::int64_t offset[3]);

/// The combined partial summaries (FieldSummary::partial) of `blocks` in a field of `global`
/// elements: empty parts (of the right cell count) for no block. Exact in any order.
FieldSummary::Parts partial_of_blocks(std::span<const FieldBlock> blocks, const std::int64_t global[3], int edge);
/// Merges `blocks` into `parts` (of a field of `global` elements with `edge`), device blocks
/// (FieldBlock::on_device) summarised on their device.
void accumulate_blocks(FieldSummary::Parts& parts, std::span<const FieldBlock> blocks, const std::int64_t global[3],
                       int edge);

/// One rank's blocks checked as assemble_one_rank checks them (each view valid; the blocks
/// tile the grid, or tessera_execute's one block covers it), reading no value: LayoutError
/// naming the fault.
void check_blocks_one_rank(std::span<const FieldBlock> blocks, const std::int64_t global[3]);

/// Finite min/max over the blocks' values (field_range of each); nullopt when none is finite.
std::optional<std::pair<double, double>> blocks_range(std::span<const FieldBlock> blocks);

/// One rank's assemble_blocks (parallel_context.h): tessera_execute's block must cover the
/// grid (LayoutError otherwise) and is returned as it is, as is one domain that covers it;
/// several domains are checked (block_layout.h) and copied into `replica` (resized to the
/// field), whose view is returned.
FieldView assemble_one_rank(std::span<const FieldBlock> blocks, const std::int64_t global[3], DType dtype,
                            std::vector<unsigned char>& replica);

/// One rank's summarize_blocks: the blocks checked as assemble_one_rank does, their partial
/// summaries combined.
std::shared_ptr<const FieldSummary> summarize_one_rank(std::span<const FieldBlock> blocks, const std::int64_t global[3],
                                                       DType dtype, int edge);

}  // namespace tessera::insitu
