// A rank's blocks on the rank itself: copies into dense arrays, combined summaries (block_ops.h).
#include "block_ops.h"

#include <tessera/render.h>

#include <algorithm>
#include <cstring>

namespace tessera::insitu {
namespace {

template <std::size_t E>
void copy_typed(const FieldView& v, unsigned char* dst0, const std::int64_t dims[3], const std::int64_t offset[3]) {
  const auto* src0 = static_cast<const unsigned char*>(v.data);
  const std::int64_t s0 = v.byte_strides[0];
  for (std::int64_t k = 0; k < v.dims[2]; ++k)
    for (std::int64_t j = 0; j < v.dims[1]; ++j) {
      const unsigned char* src = src0 + j * v.byte_strides[1] + k * v.byte_strides[2];
      unsigned char* dst = dst0 + E * (((offset[2] + k) * dims[1] + offset[1] + j) * dims[0] + offset[0]);
      if (s0 == static_cast<std::int64_t>(E)) {
        std::memcpy(dst, src, E * static_cast<std::size_t>(v.dims[0]));
      } else {
        for (std::int64_t i = 0; i < v.dims[0]; ++i) std::memcpy(dst + E * i, src + i * s0, E);
      }
    }
}

}  // namespace

void copy_block(const FieldView& v, void* dst, const std::int64_t dims[3], const std::int64_t offset[3]) {
  auto* d = static_cast<unsigned char*>(dst);
  switch (dtype_size(v.dtype)) {
    case 1: copy_typed<1>(v, d, dims, offset); break;
    case 2: copy_typed<2>(v, d, dims, offset); break;
    case 4: copy_typed<4>(v, d, dims, offset); break;
    default: copy_typed<8>(v, d, dims, offset); break;
  }
}

void combine_parts(FieldSummary::Parts& a, const FieldSummary::Parts& b) {
  for (std::size_t n = 0; n < a.lo.size(); ++n) {
    a.lo[n] = std::min(a.lo[n], b.lo[n]);
    a.hi[n] = std::max(a.hi[n], b.hi[n]);
    a.flags[n] |= b.flags[n];
  }
  a.nan += b.nan;
  a.vmin = std::min(a.vmin, b.vmin);
  a.vmax = std::max(a.vmax, b.vmax);
}

FieldSummary::Parts partial_of_blocks(std::span<const FieldBlock> blocks, const std::int64_t global[3], int edge) {
  if (blocks.empty()) return FieldSummary::partial(FieldView{}, global, global, edge);  // data null: empty parts
  FieldSummary::Parts parts = FieldSummary::partial(blocks[0].view, blocks[0].offset, global, edge);
  for (std::size_t n = 1; n < blocks.size(); ++n)
    combine_parts(parts, FieldSummary::partial(blocks[n].view, blocks[n].offset, global, edge));
  return parts;
}

std::optional<std::pair<double, double>> blocks_range(std::span<const FieldBlock> blocks) {
  std::optional<std::pair<double, double>> r;
  for (const FieldBlock& b : blocks)
    if (const auto br = field_range(b.view)) {
      if (!r) r = br;
      else r = std::pair{std::min(r->first, br->first), std::max(r->second, br->second)};
    }
  return r;
}

}  // namespace tessera::insitu
