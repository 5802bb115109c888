#pragma once
/// Whether the blocks of all ranks tile the global grid: every block inside it, no two
/// blocks' real elements overlapping, every element covered. Shared by the serial and MPI
/// contexts (parallel_context.h), which call it alike on every rank with every rank's blocks.
///
/// Cost: O(N log N) time and 16 bytes per block corner (8 corners a block) for N blocks,
/// whatever their sizes: the blocks tile the grid iff they lie inside it, their element counts
/// add up to the grid's, and every corner point except the grid's own 8 is a corner of an
/// even number of blocks (the parity of the blocks' corner points fixes how often, mod 2,
/// each element is covered: odd everywhere inside, so at least once, and with the counts
/// adding up, exactly once). Only on failure is a pair of overlapping blocks searched for
/// (a sweep along i, bounded to kMaxPairTests box comparisons) to name in the message.
#include "data/field_block.h"

#include <cstdint>
#include <span>

namespace tessera::insitu {

/// One block of one rank, as every rank sees it.
struct BlockRecord {
  std::int64_t offset[3];
  std::int64_t dims[3];
  std::int32_t rank;
  std::int32_t domain;      ///< the caller's domain index; -1: tessera_execute's single block
  std::int32_t level = 0;   ///< refinement level (amr_layout.h); 0 for a single-level mesh
  std::int32_t unused = 0;  ///< (padding, sent as bytes: kept zero)
};

/// The box comparisons the failure path makes at most to name an overlapping pair.
inline constexpr std::int64_t kMaxPairTests = 20'000'000;

/// Throws LayoutError, naming the blocks ("rank r" or "rank r domain d") and what is wrong,
/// unless `blocks` tile [0, global). `elements`: "vertices" or "cells", for the messages.
/// global: each in [1, INT_MAX] (checked: LayoutError).
void check_tiling(std::span<const BlockRecord> blocks, const std::int64_t global[3], const char* elements);

/// "rank r" or "rank r domain d".
std::string block_name(const BlockRecord& b);

}  // namespace tessera::insitu
