#pragma once
/// MagnitudeFieldView: how the kernels read a MagnitudeField (magnitude_field.h) in place:
/// each vertex is magnitude() of the three components' elements, each component read with its
/// own dtype and byte strides (the dtype switched per load, as for a paged field). Trivially
/// copyable; points at the caller's arrays. Inactive (base[0] null) for every other field.
#include <tessera/brick_cache.h>
#include <tessera/field_view.h>
#include <tessera/host_device.h>
#include <tessera/magnitude_field.h>

#include <cstdint>
#include <type_traits>

namespace tessera {

struct MagnitudeFieldView {
  const unsigned char* base[3] = {nullptr, nullptr, nullptr};
  std::int64_t s[3][3] = {};  ///< per component, byte strides along i, j, k
  DType dtype[3] = {DType::Float64, DType::Float64, DType::Float64};

  TESSERA_HOST_DEVICE bool active() const { return base[0] != nullptr; }

  static MagnitudeFieldView of(const MagnitudeField& f) {
    MagnitudeFieldView v;
    for (int c = 0; c < 3; ++c) {
      v.base[c] = static_cast<const unsigned char*>(f.components[c].data);
      v.dtype[c] = f.components[c].dtype;
      for (int a = 0; a < 3; ++a) v.s[c][a] = f.components[c].byte_strides[a];
    }
    return v;
  }

  [[gnu::always_inline]] TESSERA_HOST_DEVICE double component(int c, std::int64_t i, std::int64_t j,
                                                              std::int64_t k) const {
    return detail::load_as_double(dtype[c], base[c] + i * s[c][0] + j * s[c][1] + k * s[c][2]);
  }
  /// magnitude() of vertex (i, j, k)'s components.
  TESSERA_HOST_DEVICE double load(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return magnitude(component(0, i, j, k), component(1, i, j, k), component(2, i, j, k));
  }
};
static_assert(std::is_trivially_copyable_v<MagnitudeFieldView>);

}  // namespace tessera
