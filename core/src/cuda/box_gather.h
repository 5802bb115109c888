#pragma once
/// The host half of cuda_copy_box_to_host (cuda_memory.h): a view's elements gathered densely,
/// x fastest, for a view the host can read (host or managed memory, an emulated GPU's).
#include <tessera/copy_box.h>

#include <cstdint>

namespace tessera::cuda {

inline void gather_box(void* dst, const FieldView& box) {
  const auto e = static_cast<std::int64_t>(dtype_size(box.dtype));
  const std::int64_t dense[3] = {e, e * box.dims[0], e * box.dims[0] * box.dims[1]};
  copy_box(box, dst, dense);
}

}  // namespace tessera::cuda
