#pragma once
/// The bytes a strided array occupies (host code of the CUDA backend): the lowest and one
/// past the highest byte of its elements, as offsets from element (0, 0, 0). Negative strides
/// reach below it. What a host array's device copy holds, and no more.
#include <cstddef>
#include <cstdint>

namespace tessera::cuda {

struct StridedSpan {
  std::int64_t lo = 0;  ///< <= 0
  std::int64_t hi = 0;  ///< > 0
};

inline StridedSpan strided_span(const std::int64_t dims[3], const std::int64_t byte_strides[3], std::size_t elem) {
  StridedSpan s{0, static_cast<std::int64_t>(elem)};
  for (int a = 0; a < 3; ++a) {
    const std::int64_t reach = (dims[a] - 1) * byte_strides[a];
    if (reach < 0) s.lo += reach;
    else s.hi += reach;
  }
  return s;
}

}  // namespace tessera::cuda
