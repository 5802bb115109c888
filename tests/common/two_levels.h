#pragma once
/// Test input for the core's refinement levels (tessera::AmrField, without the C API): a
/// level-0 grid of n0^3 elements refined once by 2, over patches the caller keeps alive.
#include <tessera/amr.h>

#include <cstdint>
#include <span>

namespace tessera_test {

/// Patch of `level` at `offset` (elements of its level) over a contiguous array of `dims`.
inline tessera::AmrPatch contiguous_patch(int level, const std::int64_t offset[3], const void* data,
                                          tessera::DType dtype, const std::int64_t dims[3]) {
  tessera::AmrPatch p;
  p.level = level;
  for (int a = 0; a < 3; ++a) p.offset[a] = offset[a];
  p.view = tessera::FieldView::contiguous(data, dtype, dims[0], dims[1], dims[2]);
  return p;
}

/// Two levels (ratio 2) of `dtype` over level-0 dims n0^3 and `patches` (read, not copied).
inline tessera::AmrField two_levels(tessera::DType dtype, std::int64_t n0, std::span<const tessera::AmrPatch> patches) {
  tessera::AmrField amr;
  amr.dtype = dtype;
  for (int a = 0; a < 3; ++a) amr.dims[a] = n0;
  amr.nlevels = 2;
  amr.ratio[0] = 2;
  amr.patches = patches;
  return amr;
}

}  // namespace tessera_test
