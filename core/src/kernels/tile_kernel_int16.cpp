/// The tile and preview kernels for int16 fields (uniform, and with rectilinear axes).
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(std::int16_t);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<std::int16_t>);
}  // namespace tessera
