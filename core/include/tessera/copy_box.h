#pragma once
/// copy_box: a strided box's elements into another strided box, on the host.
#include <tessera/field_view.h>

#include <cstdint>

namespace tessera {

/// Copies the elements of `from` (host-readable memory, any byte strides) into the box of the
/// same dims and dtype at `to`, whose byte strides are `to_strides` (e.g. a dense array, or a
/// block's place in a larger one); rows whose elements are adjacent on both sides are one
/// memcpy each. The boxes must not overlap.
void copy_box(const FieldView& from, void* to, const std::int64_t to_strides[3]);

}  // namespace tessera
