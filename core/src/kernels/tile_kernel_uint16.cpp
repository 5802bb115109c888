/// The tile and preview kernels for uint16 fields (uniform, and with rectilinear axes).
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(std::uint16_t);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<std::uint16_t>);
}  // namespace tessera
