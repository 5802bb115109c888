/// The tile and preview kernels for uint16 fields (uniform, and with rectilinear axes).
#define TESSERA_EMULATED_SLICE_DEFINITION
#include "kernels/emulated_slice.h"
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(std::uint16_t);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<std::uint16_t>);
}  // namespace tessera

// The host emulation of the GPU backend's slices for the same Values (kernels/emulated_slice.h)
TESSERA_INSTANTIATE_EMULATED_SLICE(std::uint16_t);
TESSERA_INSTANTIATE_EMULATED_SLICE(tessera::Rectilinear<std::uint16_t>);
