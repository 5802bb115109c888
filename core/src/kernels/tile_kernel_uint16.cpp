/// The tile and preview kernels for uint16 fields.
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(std::uint16_t);
}  // namespace tessera
