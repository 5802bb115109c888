#pragma once
/// The host half of cuda_copy_box_to_host (cuda_memory.h): a view's elements gathered densely,
/// x fastest, for a view the host can read (host or managed memory, an emulated GPU's).
#include <tessera/copy_box.h>

#include <cstdint>

namespace tessera::cuda {

inline void gather_box(void* dst, const FieldView& box) {
  copy_box(box, dst, FieldView::contiguous(dst, box.dtype, box.dims[0], box.dims[1], box.dims[2]).byte_strides);
}

}  // namespace tessera::cuda
