#pragma once
/// The bytes a strided array occupies: what a copy of it (to or from a device) must hold, and
/// no more. Used by the GPU backend's device copies and the in situ adapter's staging.
#include <tessera/field_view.h>

#include <cstddef>
#include <cstdint>

namespace tessera {

/// Offsets from element (0, 0, 0) of the lowest byte and one past the highest byte of the
/// array's elements: lo <= 0 (negative strides reach below element 0), hi > 0.
struct ByteSpan {
  std::int64_t lo = 0;
  std::int64_t hi = 0;
  std::int64_t bytes() const { return hi - lo; }
};

/// The span of dims elements of `elem` bytes at byte_strides (dims >= 1).
inline ByteSpan byte_span(const std::int64_t dims[3], const std::int64_t byte_strides[3], std::size_t elem) {
  ByteSpan s{0, static_cast<std::int64_t>(elem)};
  for (int a = 0; a < 3; ++a) {
    const std::int64_t reach = (dims[a] - 1) * byte_strides[a];
    if (reach < 0) s.lo += reach;
    else s.hi += reach;
  }
  return s;
}

/// The span of a field view's elements.
inline ByteSpan byte_span(const FieldView& v) { return byte_span(v.dims, v.byte_strides, dtype_size(v.dtype)); }

}  // namespace tessera
