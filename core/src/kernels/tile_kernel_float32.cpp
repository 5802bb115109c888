/// The tile and preview kernels for float32 fields, every mode combination.
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(float);
}  // namespace tessera
