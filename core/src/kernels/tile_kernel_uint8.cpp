/// The tile and preview kernels for uint8 fields.
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(std::uint8_t);
}  // namespace tessera
