#pragma once
/// FieldView: a non-owning, zero-copy view of a 3D scalar array that someone else owns.
///
/// The view addresses element (i, j, k) at `data + i*byte_strides[0] + j*byte_strides[1] +
/// k*byte_strides[2]`, for 0 <= i < dims[0] etc. `data` points at the first *real* vertex
/// (ghost layers already skipped, see `with_ghosts`). Strides are in bytes and may be any
/// positive multiple of nothing in particular: C order, Fortran order, a sub-box of a larger
/// array and one component of an array of structs are all expressible. Negative strides are
/// allowed (mirrored arrays). The viewed memory must stay valid and unchanged while a render
/// that uses it runs; the renderer only reads it and never copies, converts or re-bricks it.
#include <tessera/host_device.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>

namespace tessera {

enum class DType : int { UInt8 = 0, Int16, UInt16, Float32, Float64 };

/// Size in bytes of one element of `t`.
std::size_t dtype_size(DType t);
/// Lower-case name as used in configs: uint8 int16 uint16 float32 float64.
const char* dtype_name(DType t);

struct FieldView {
  const void* data = nullptr;  ///< first real vertex
  DType dtype = DType::Float32;
  std::int64_t dims[3] = {0, 0, 0};  ///< real vertices along i, j, k (each >= 1)
  std::int64_t byte_strides[3] = {0, 0, 0};

  /// Dense C-order view (k slowest... i fastest): strides sizeof(T), nx*sizeof(T), nx*ny*sizeof(T).
  static FieldView contiguous(const void* data, DType dtype, std::int64_t nx, std::int64_t ny, std::int64_t nz);

  /// View of the real region of an array that holds ghost layers: `full_dims` is the extent
  /// including ghosts, `base` its first element (ghost included). Throws std::invalid_argument
  /// naming the fault when ghosts leave no real vertex.
  static FieldView with_ghosts(const void* base, DType dtype, const std::int64_t full_dims[3],
                               const std::int64_t byte_strides[3], const std::int64_t ghosts_lo[3],
                               const std::int64_t ghosts_hi[3]);

  std::int64_t vertex_count() const { return dims[0] * dims[1] * dims[2]; }

  /// Throws std::invalid_argument with a message naming `what` and the fault: null data,
  /// dims < 1, zero stride, or strides under which two distinct vertices share bytes.
  void validate(const std::string& what = "field") const;
};
static_assert(std::is_trivially_copyable_v<FieldView>);

/// Typed accessor used by the kernels: the dtype switch happens once per frame, then every
/// lookup is a plain load. Converting to double is exact for every supported dtype.
template <class T>
struct TypedFieldView {
  using value_type = T;
  const unsigned char* base;
  std::int64_t sx, sy, sz;
  TESSERA_HOST_DEVICE double load(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return load_at(base + i * sx + j * sy + k * sz);
  }
  /// The sample whose first byte is q (q inside the array; any alignment).
  TESSERA_HOST_DEVICE static double load_at(const unsigned char* q) {
    T v;
    __builtin_memcpy(&v, q, sizeof(T));
    return static_cast<double>(v);
  }
};

template <class T>
TypedFieldView<T> typed(const FieldView& f) {
  return {static_cast<const unsigned char*>(f.data), f.byte_strides[0], f.byte_strides[1], f.byte_strides[2]};
}

/// Calls fn(TypedFieldView<T>) with T the C++ type of f.dtype.
template <class Fn>
decltype(auto) dispatch_dtype(const FieldView& f, Fn&& fn) {
  switch (f.dtype) {
    case DType::UInt8: return fn(typed<std::uint8_t>(f));
    case DType::Int16: return fn(typed<std::int16_t>(f));
    case DType::UInt16: return fn(typed<std::uint16_t>(f));
    case DType::Float32: return fn(typed<float>(f));
    case DType::Float64:
    default: return fn(typed<double>(f));
  }
}

}  // namespace tessera
