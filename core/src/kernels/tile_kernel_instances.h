#pragma once
/// The kernels of one field Value (a dtype's C++ type, or PagedValue, each also as
/// Rectilinear<>), each Value's compiled in its own translation unit (tile_kernel_<value>.cpp) so that they build in parallel.
/// tile_kernel() / preview_kernel() (tile_kernel.cpp) pick the Value.
#include "kernel/grid_medium.h"
#include "kernels/tile_kernel.h"

#include <cstdint>

namespace tessera {

template <class V>
TileKernel tile_kernel_for();
template <class V>
PreviewKernel preview_kernel_for();

/// Instantiates both for V (in tile_kernel_<value>.cpp, after including tile_kernel_impl.h).
#define TESSERA_INSTANTIATE_TILE_KERNELS(V) \
  template TileKernel tile_kernel_for<V>(); \
  template PreviewKernel preview_kernel_for<V>()

extern template TileKernel tile_kernel_for<std::uint8_t>();
extern template TileKernel tile_kernel_for<std::int16_t>();
extern template TileKernel tile_kernel_for<std::uint16_t>();
extern template TileKernel tile_kernel_for<float>();
extern template TileKernel tile_kernel_for<double>();
extern template TileKernel tile_kernel_for<PagedValue>();
extern template TileKernel tile_kernel_for<AmrValue>();
extern template PreviewKernel preview_kernel_for<std::uint8_t>();
extern template PreviewKernel preview_kernel_for<std::int16_t>();
extern template PreviewKernel preview_kernel_for<std::uint16_t>();
extern template PreviewKernel preview_kernel_for<float>();
extern template PreviewKernel preview_kernel_for<double>();
extern template PreviewKernel preview_kernel_for<PagedValue>();
extern template PreviewKernel preview_kernel_for<AmrValue>();
// With some rectilinear axis (grid_medium.h), in the same translation units
extern template TileKernel tile_kernel_for<Rectilinear<std::uint8_t>>();
extern template PreviewKernel preview_kernel_for<Rectilinear<std::uint8_t>>();
extern template TileKernel tile_kernel_for<Rectilinear<std::int16_t>>();
extern template PreviewKernel preview_kernel_for<Rectilinear<std::int16_t>>();
extern template TileKernel tile_kernel_for<Rectilinear<std::uint16_t>>();
extern template PreviewKernel preview_kernel_for<Rectilinear<std::uint16_t>>();
extern template TileKernel tile_kernel_for<Rectilinear<float>>();
extern template PreviewKernel preview_kernel_for<Rectilinear<float>>();
extern template TileKernel tile_kernel_for<Rectilinear<double>>();
extern template PreviewKernel preview_kernel_for<Rectilinear<double>>();
extern template TileKernel tile_kernel_for<Rectilinear<PagedValue>>();
extern template PreviewKernel preview_kernel_for<Rectilinear<PagedValue>>();
// A vector's magnitude (tile_kernel_magnitude.cpp)
extern template TileKernel tile_kernel_for<MagnitudeValue>();
extern template PreviewKernel preview_kernel_for<MagnitudeValue>();
extern template TileKernel tile_kernel_for<Rectilinear<MagnitudeValue>>();
extern template PreviewKernel preview_kernel_for<Rectilinear<MagnitudeValue>>();
// A curvilinear or unstructured mesh (tile_kernel_mesh.cpp, kernel/mesh_medium.h)
extern template TileKernel tile_kernel_for<MeshValue>();
extern template PreviewKernel preview_kernel_for<MeshValue>();

}  // namespace tessera
