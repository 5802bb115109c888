/// The tile and preview kernels for float32 fields (uniform, and with rectilinear axes).
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(float);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<float>);
}  // namespace tessera
