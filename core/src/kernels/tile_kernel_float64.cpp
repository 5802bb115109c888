/// The tile and preview kernels for float64 fields.
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(double);
}  // namespace tessera
