#pragma once
/// The host half of cuda_copy_box_to_host (cuda_memory.h): a view's elements gathered densely,
/// x fastest, for a view the host can read (host or managed memory, an emulated GPU's).
#include <tessera/field_view.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace tessera::cuda {

inline void gather_box(void* dst, const FieldView& box) {
  const auto e = static_cast<std::int64_t>(dtype_size(box.dtype));
  const auto* base = static_cast<const unsigned char*>(box.data);
  auto* out = static_cast<unsigned char*>(dst);
  const std::int64_t nx = box.dims[0];
  for (std::int64_t k = 0; k < box.dims[2]; ++k)
    for (std::int64_t j = 0; j < box.dims[1]; ++j) {
      const unsigned char* row = base + j * box.byte_strides[1] + k * box.byte_strides[2];
      if (box.byte_strides[0] == e) {
        std::memcpy(out, row, static_cast<std::size_t>(nx * e));
      } else {
        for (std::int64_t i = 0; i < nx; ++i)
          std::memcpy(out + i * e, row + i * box.byte_strides[0], static_cast<std::size_t>(e));
      }
      out += nx * e;
    }
}

}  // namespace tessera::cuda
