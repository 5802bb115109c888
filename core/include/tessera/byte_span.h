#pragma once
/// The bytes a strided array occupies: what a copy of it (to or from a device) must hold, and
/// no more; several arrays' spans merged where they overlap. Used by the GPU backend's device
/// copies and the in situ adapter's staging.
#include <tessera/field_view.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

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

/// One array's bytes [lo, hi) where they lie, and the caller's tag for it.
struct AddressSpan {
  const unsigned char* lo = nullptr;
  const unsigned char* hi = nullptr;
  int tag = 0;
};

/// Arrays whose spans overlap or touch, as one span [lo, hi): spans[first, last) after
/// merge_spans sorted them.
struct SpanRun {
  const unsigned char* lo = nullptr;
  const unsigned char* hi = nullptr;
  std::size_t first = 0, last = 0;
};

/// Sorts `spans` by address and groups them into runs whose spans overlap or touch (x, y and z
/// interleaved in one array make one run): one copy per run then holds every array once, and
/// none reads a byte between two arrays that belongs to neither.
inline std::vector<SpanRun> merge_spans(std::vector<AddressSpan>& spans) {
  std::sort(spans.begin(), spans.end(), [](const AddressSpan& a, const AddressSpan& b) { return a.lo < b.lo; });
  std::vector<SpanRun> runs;
  for (std::size_t i = 0; i < spans.size(); ++i) {
    if (!runs.empty() && spans[i].lo <= runs.back().hi) {
      runs.back().last = i + 1;
      runs.back().hi = std::max(runs.back().hi, spans[i].hi);
    } else {
      runs.push_back({spans[i].lo, spans[i].hi, i, i + 1});
    }
  }
  return runs;
}

}  // namespace tessera
