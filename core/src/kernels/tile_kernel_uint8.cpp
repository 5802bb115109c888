/// The tile and preview kernels for uint8 fields (uniform, and with rectilinear axes).
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(std::uint8_t);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<std::uint8_t>);
}  // namespace tessera
