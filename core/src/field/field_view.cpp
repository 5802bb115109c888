#include <tessera/field_view.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace tessera {

std::size_t dtype_size(DType t) {
  switch (t) {
    case DType::UInt8: return 1;
    case DType::Int16: return 2;
    case DType::UInt16: return 2;
    case DType::Float32: return 4;
    case DType::Float64: return 8;
  }
  throw std::invalid_argument("unknown dtype " + std::to_string(static_cast<int>(t)));
}

const char* dtype_name(DType t) {
  switch (t) {
    case DType::UInt8: return "uint8";
    case DType::Int16: return "int16";
    case DType::UInt16: return "uint16";
    case DType::Float32: return "float32";
    case DType::Float64: return "float64";
  }
  return "unknown";
}

FieldView FieldView::contiguous(const void* data, DType dtype, std::int64_t nx, std::int64_t ny, std::int64_t nz) {
  const auto s = static_cast<std::int64_t>(dtype_size(dtype));
  FieldView v;
  v.data = data;
  v.dtype = dtype;
  v.dims[0] = nx;
  v.dims[1] = ny;
  v.dims[2] = nz;
  v.byte_strides[0] = s;
  v.byte_strides[1] = s * nx;
  v.byte_strides[2] = s * nx * ny;
  return v;
}

FieldView FieldView::with_ghosts(const void* base, DType dtype, const std::int64_t full_dims[3],
                                 const std::int64_t byte_strides[3], const std::int64_t ghosts_lo[3],
                                 const std::int64_t ghosts_hi[3]) {
  static const char* axis = "ijk";
  FieldView v;
  v.dtype = dtype;
  std::int64_t offset = 0;
  for (int a = 0; a < 3; ++a) {
    if (ghosts_lo[a] < 0 || ghosts_hi[a] < 0)
      throw std::invalid_argument(std::string("negative ghost width along ") + axis[a]);
    v.dims[a] = full_dims[a] - ghosts_lo[a] - ghosts_hi[a];
    if (v.dims[a] < 1)
      throw std::invalid_argument(std::string("ghost layers along ") + axis[a] + " (" + std::to_string(ghosts_lo[a]) +
                                  " + " + std::to_string(ghosts_hi[a]) + ") leave no real vertex of " +
                                  std::to_string(full_dims[a]));
    v.byte_strides[a] = byte_strides[a];
    offset += ghosts_lo[a] * byte_strides[a];
  }
  v.data = base ? static_cast<const unsigned char*>(base) + offset : nullptr;
  return v;
}

void FieldView::validate(const std::string& what) const {
  static const char* axis = "ijk";
  if (!data) throw std::invalid_argument(what + ": data pointer is null");
  const auto es = static_cast<std::int64_t>(dtype_size(dtype));
  for (int a = 0; a < 3; ++a) {
    if (dims[a] < 1)
      throw std::invalid_argument(what + ": dims[" + std::to_string(a) + "] (" + axis[a] +
                                  ") = " + std::to_string(dims[a]) + ", must be >= 1");
    if (dims[a] > 1 && std::llabs(byte_strides[a]) < es)
      throw std::invalid_argument(what + ": byte stride along " + axis[a] + " is " + std::to_string(byte_strides[a]) +
                                  ", smaller than the " + std::to_string(es) + "-byte element");
  }
  // Overlap check: sort axes by |stride|; each must step over the whole extent of the smaller.
  std::array<int, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return std::llabs(byte_strides[a]) < std::llabs(byte_strides[b]); });
  std::int64_t extent = es;  // bytes spanned by the axes seen so far
  for (int a : order) {
    if (dims[a] == 1) continue;
    const std::int64_t s = std::llabs(byte_strides[a]);
    if (s < extent)
      throw std::invalid_argument(what + ": byte strides overlap: stride " + std::to_string(byte_strides[a]) +
                                  " along " + axis[a] + " is smaller than the " + std::to_string(extent) +
                                  " bytes spanned by the faster axes");
    extent = s * (dims[a] - 1) + extent;
  }
}

}  // namespace tessera
