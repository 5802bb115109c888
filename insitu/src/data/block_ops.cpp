// A rank's blocks on the rank itself: copies into dense arrays, combined summaries (block_ops.h).
#include "data/block_ops.h"

#include "data/block_layout.h"

#include <tessera/copy_box.h>
#include <tessera/cuda_render.h>
#include <tessera/render.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace tessera::insitu {
namespace {

/// field_range of a block in device memory, computed on its device (a summary of one
/// macrocell: only its range comes back).
std::optional<std::pair<double, double>> device_block_range(const FieldBlock& b) {
  const std::int64_t longest = std::max({b.view.dims[0], b.view.dims[1], b.view.dims[2], std::int64_t{2}});
  const int edge = static_cast<int>(std::min<std::int64_t>(longest, std::numeric_limits<int>::max()));
  const std::shared_ptr<const FieldSummary> s = cuda_field_summary(b.view, edge, b.cuda_stream);
  if (!s->has_finite()) return std::nullopt;
  return std::pair{s->value_min(), s->value_max()};
}

}  // namespace

void copy_block(const FieldView& v, void* dst, const std::int64_t dims[3], const std::int64_t offset[3]) {
  const FieldView whole = FieldView::contiguous(dst, v.dtype, dims[0], dims[1], dims[2]);
  const std::int64_t* s = whole.byte_strides;
  copy_box(v, static_cast<unsigned char*>(dst) + offset[0] * s[0] + offset[1] * s[1] + offset[2] * s[2], s);
}

FieldSummary::Parts partial_of_blocks(std::span<const FieldBlock> blocks, const std::int64_t global[3], int edge) {
  // One set of global parts, each block merged in at the cost of its own vertices and cells
  // (not a full-size partial per block: 10^4 small domains stay cheap)
  FieldSummary::Parts parts = FieldSummary::partial(FieldView{}, global, global, edge);  // data null: empty parts
  accumulate_blocks(parts, blocks, global, edge);
  return parts;
}

void accumulate_blocks(FieldSummary::Parts& parts, std::span<const FieldBlock> blocks, const std::int64_t global[3],
                       int edge) {
  for (const FieldBlock& b : blocks) {
    if (b.on_device) cuda_field_summary_accumulate(parts, b.view, b.offset, global, edge, b.cuda_stream);
    else FieldSummary::accumulate(parts, b.view, b.offset, global, edge);
  }
}

std::optional<std::pair<double, double>> blocks_range(std::span<const FieldBlock> blocks) {
  std::optional<std::pair<double, double>> r;
  for (const FieldBlock& b : blocks)
    if (const auto br = b.on_device ? device_block_range(b) : field_range(b.view)) {
      if (!r) r = br;
      else r = std::pair{std::min(r->first, br->first), std::max(r->second, br->second)};
    }
  return r;
}

namespace {

std::string box_text(const std::int64_t offset[3], const std::int64_t dims[3]) {
  return std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) + " at offset (" +
         std::to_string(offset[0]) + ", " + std::to_string(offset[1]) + ", " + std::to_string(offset[2]) + ")";
}

/// The blocks tile the grid (block_layout.h), or for tessera_execute's one block, cover it.
/// True: one block covering the grid (read in place).
bool check_one_rank(std::span<const FieldBlock> blocks, const std::int64_t global[3]) {
  for (const FieldBlock& b : blocks) b.view.validate(b.domain >= 0 ? "domain " + std::to_string(b.domain) : "field");
  if (blocks.size() == 1 && blocks[0].domain < 0) {
    for (int a = 0; a < 3; ++a)
      if (blocks[0].offset[a] != 0 || blocks[0].view.dims[a] != global[a])
        throw LayoutError("one rank must hold the whole grid: its real vertices " +
                          box_text(blocks[0].offset, blocks[0].view.dims) + " do not cover global_dims " +
                          std::to_string(global[0]) + "x" + std::to_string(global[1]) + "x" +
                          std::to_string(global[2]));
    return true;
  }
  std::vector<BlockRecord> records(blocks.size());
  for (std::size_t n = 0; n < blocks.size(); ++n) {
    for (int a = 0; a < 3; ++a) {
      records[n].offset[a] = blocks[n].offset[a];
      records[n].dims[a] = blocks[n].view.dims[a];
    }
    records[n].rank = 0;
    records[n].domain = blocks[n].domain;
  }
  check_tiling(records, global, "elements");
  return blocks.size() == 1;
}

}  // namespace

void check_blocks_one_rank(std::span<const FieldBlock> blocks, const std::int64_t global[3]) {
  check_one_rank(blocks, global);
}

FieldView assemble_one_rank(std::span<const FieldBlock> blocks, const std::int64_t global[3], DType dtype,
                            std::vector<unsigned char>& replica) {
  if (check_one_rank(blocks, global)) return blocks[0].view;  // zero copy
  const std::size_t bytes = static_cast<std::size_t>(global[0] * global[1] * global[2]) * dtype_size(dtype);
  if (replica.size() != bytes) {
    replica.clear();
    replica.shrink_to_fit();
    replica.resize(bytes);
  }
  for (const FieldBlock& b : blocks) copy_block(b.view, replica.data(), global, b.offset);
  return FieldView::contiguous(replica.data(), dtype, global[0], global[1], global[2]);
}

std::shared_ptr<const FieldSummary> summarize_one_rank(std::span<const FieldBlock> blocks, const std::int64_t global[3],
                                                       DType dtype, int edge) {
  if (check_one_rank(blocks, global) && blocks[0].domain < 0) return FieldSummary::build(blocks[0].view, edge);
  FieldView primary;
  primary.dtype = dtype;
  if (!blocks.empty()) primary = blocks[0].view;
  return FieldSummary::from_parts(partial_of_blocks(blocks, global, edge), FieldLayout::of(primary), edge);
}

}  // namespace tessera::insitu
