// copy_box (copy_box.h): a strided box's elements into another strided box.
#include <tessera/copy_box.h>

#include <cstring>

namespace tessera {
namespace {

template <std::size_t E>
void copy_rows(const FieldView& from, unsigned char* to, const std::int64_t t[3]) {
  const auto* src0 = static_cast<const unsigned char*>(from.data);
  const std::int64_t s0 = from.byte_strides[0];
  const bool rows = s0 == static_cast<std::int64_t>(E) && t[0] == static_cast<std::int64_t>(E);
  for (std::int64_t k = 0; k < from.dims[2]; ++k)
    for (std::int64_t j = 0; j < from.dims[1]; ++j) {
      const unsigned char* src = src0 + j * from.byte_strides[1] + k * from.byte_strides[2];
      unsigned char* dst = to + j * t[1] + k * t[2];
      if (rows) {
        std::memcpy(dst, src, E * static_cast<std::size_t>(from.dims[0]));
      } else {
        for (std::int64_t i = 0; i < from.dims[0]; ++i) std::memcpy(dst + i * t[0], src + i * s0, E);
      }
    }
}

}  // namespace

void copy_box(const FieldView& from, void* to, const std::int64_t to_strides[3]) {
  auto* d = static_cast<unsigned char*>(to);
  switch (dtype_size(from.dtype)) {
    case 1: copy_rows<1>(from, d, to_strides); break;
    case 2: copy_rows<2>(from, d, to_strides); break;
    case 4: copy_rows<4>(from, d, to_strides); break;
    default: copy_rows<8>(from, d, to_strides); break;
  }
}

}  // namespace tessera
