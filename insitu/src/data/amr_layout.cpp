// Every rank's boxes of a hierarchy, checked; its patches in place or in a replica (amr_layout.h).
#include "data/amr_layout.h"

#include "data/field_plan.h"

#include <algorithm>
#include <stdexcept>

namespace tessera::insitu {
namespace {

std::uint64_t box_bytes(const BlockRecord& b, DType dtype) {
  return static_cast<std::uint64_t>(b.dims[0]) * static_cast<std::uint64_t>(b.dims[1]) *
         static_cast<std::uint64_t>(b.dims[2]) * dtype_size(dtype);
}

AmrPatch patch_of(const BlockRecord& b, const FieldView& view) {
  AmrPatch p;
  p.level = b.level;
  for (int a = 0; a < 3; ++a) p.offset[a] = b.offset[a];
  p.view = view;
  return p;
}

}  // namespace

std::uint64_t AmrLayout::patch_bytes() const {
  std::uint64_t sum = 0;
  for (const BlockRecord& b : boxes) sum += box_bytes(b, meta.dtype);
  return sum;
}

std::vector<std::uint64_t> AmrLayout::replica_offsets() const {
  std::vector<std::uint64_t> at(boxes.size());
  std::uint64_t sum = 0;
  for (std::size_t n = 0; n < boxes.size(); ++n) {
    at[n] = sum;
    sum += box_bytes(boxes[n], meta.dtype);
  }
  return at;
}

std::uint64_t AmrLayout::table_bytes(int edge) const {
  // The boxes as patches over a placeholder address: amr_table_bytes reads no value
  static const unsigned char kPlaceholder[8] = {};
  std::vector<AmrPatch> patches;
  patches.reserve(boxes.size());
  for (const BlockRecord& b : boxes)
    patches.push_back(patch_of(b, FieldView::contiguous(kPlaceholder, meta.dtype, b.dims[0], b.dims[1], b.dims[2])));
  AmrField f = meta;
  f.names.clear();
  f.patches = patches;
  return amr_table_bytes(f, assoc, edge);
}

AmrVirtualLayout AmrLayout::virtual_grid() const {
  std::vector<AmrBox> b(boxes.size());
  for (std::size_t n = 0; n < boxes.size(); ++n) {
    b[n].level = boxes[n].level;
    for (int a = 0; a < 3; ++a) {
      b[n].offset[a] = boxes[n].offset[a];
      b[n].dims[a] = boxes[n].dims[a];
    }
  }
  return amr_virtual_layout(meta, assoc, b, kMaxBrickShift);
}

std::vector<AmrPatch> patches_distributed(std::span<const FieldBlock> ordered, const AmrLayout& layout, int rank) {
  std::vector<AmrPatch> patches;
  patches.reserve(layout.boxes.size());
  std::size_t own = 0;
  for (const BlockRecord& b : layout.boxes) {
    if (b.rank == rank) {
      if (own >= ordered.size()) throw std::logic_error("patches_distributed: more own boxes than blocks");
      patches.push_back(patch_of(b, ordered[own++].view));
      continue;
    }
    FieldView none;  // another rank's: dims and dtype only
    none.dtype = layout.meta.dtype;
    for (int a = 0; a < 3; ++a) none.dims[a] = b.dims[a];
    patches.push_back(patch_of(b, none));
  }
  return patches;
}

std::vector<FieldBlock> virtual_blocks(std::span<const FieldBlock> ordered, const AmrVirtualLayout& v) {
  std::vector<FieldBlock> out(ordered.begin(), ordered.end());
  for (FieldBlock& b : out)
    for (int a = 0; a < 3; ++a) b.offset[a] += v.base[b.level][a];
  return out;
}

std::vector<BlockRecord> virtual_records(const AmrLayout& layout, const AmrVirtualLayout& v) {
  std::vector<BlockRecord> out = layout.boxes;
  for (BlockRecord& b : out)
    for (int a = 0; a < 3; ++a) b.offset[a] += v.base[b.level][a];
  return out;
}

AmrField amr_meta(const FieldBinding& binding, DType dtype) {
  AmrField f;
  f.dtype = dtype;
  for (int a = 0; a < 3; ++a) f.dims[a] = binding.placement.global_dims[a];
  f.nlevels = binding.nlevels;
  for (int l = 0; l + 1 < binding.nlevels; ++l) f.ratio[l] = binding.refinement[l];
  return f;
}

std::vector<FieldBlock> in_domain_order(std::span<const FieldBlock> blocks) {
  std::vector<FieldBlock> v(blocks.begin(), blocks.end());
  std::stable_sort(v.begin(), v.end(), [](const FieldBlock& x, const FieldBlock& y) { return x.domain < y.domain; });
  return v;
}

std::vector<BlockRecord> block_records(std::span<const FieldBlock> ordered, int rank) {
  std::vector<BlockRecord> own(ordered.size());
  for (std::size_t n = 0; n < ordered.size(); ++n) {
    for (int a = 0; a < 3; ++a) {
      own[n].offset[a] = ordered[n].offset[a];
      own[n].dims[a] = ordered[n].view.dims[a];
    }
    own[n].rank = rank;
    own[n].domain = ordered[n].domain;
    own[n].level = ordered[n].level;
  }
  return own;
}

AmrLayout check_amr_layout(std::vector<BlockRecord> boxes, std::vector<int> counts, const AmrField& meta,
                           Association assoc) {
  AmrLayout layout;
  layout.meta = meta;
  layout.meta.patches = {};
  layout.meta.names.clear();
  layout.assoc = assoc;
  layout.boxes = std::move(boxes);
  layout.counts = std::move(counts);
  std::vector<AmrBox> amr(layout.boxes.size());
  for (std::size_t n = 0; n < amr.size(); ++n) {
    amr[n].level = layout.boxes[n].level;
    for (int a = 0; a < 3; ++a) {
      amr[n].offset[a] = layout.boxes[n].offset[a];
      amr[n].dims[a] = layout.boxes[n].dims[a];
    }
  }
  try {
    check_amr_boxes(layout.meta, assoc, amr, [&](std::size_t n) { return block_name(layout.boxes[n]); });
  } catch (const std::invalid_argument& e) {
    throw LayoutError(e.what());
  }
  layout.meta.names.reserve(layout.boxes.size());
  for (const BlockRecord& b : layout.boxes) layout.meta.names.push_back(block_name(b));
  return layout;
}

AmrLayout amr_layout_one_rank(std::span<const FieldBlock> blocks, const AmrField& meta, Association assoc) {
  const std::vector<FieldBlock> ordered = in_domain_order(blocks);
  for (const FieldBlock& b : ordered) {
    try {
      b.view.validate("domain " + std::to_string(b.domain));
    } catch (const std::exception& e) {
      throw LayoutError(e.what());
    }
  }
  return check_amr_layout(block_records(ordered, 0), {static_cast<int>(ordered.size())}, meta, assoc);
}

std::vector<AmrPatch> patches_in_place(std::span<const FieldBlock> ordered, const AmrLayout& layout) {
  if (ordered.size() != layout.boxes.size())
    throw std::logic_error("patches_in_place: " + std::to_string(ordered.size()) + " blocks for " +
                           std::to_string(layout.boxes.size()) + " boxes");
  std::vector<AmrPatch> patches;
  patches.reserve(ordered.size());
  for (std::size_t n = 0; n < ordered.size(); ++n) patches.push_back(patch_of(layout.boxes[n], ordered[n].view));
  return patches;
}

std::vector<AmrPatch> patches_in_replica(const void* base, const AmrLayout& layout) {
  const std::vector<std::uint64_t> at = layout.replica_offsets();
  std::vector<AmrPatch> patches;
  patches.reserve(layout.boxes.size());
  for (std::size_t n = 0; n < layout.boxes.size(); ++n) {
    const BlockRecord& b = layout.boxes[n];
    patches.push_back(patch_of(b, FieldView::contiguous(static_cast<const unsigned char*>(base) + at[n],
                                                        layout.meta.dtype, b.dims[0], b.dims[1], b.dims[2])));
  }
  return patches;
}

}  // namespace tessera::insitu
