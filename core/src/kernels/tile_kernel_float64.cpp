/// The tile and preview kernels for float64 fields (uniform, and with rectilinear axes).
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(double);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<double>);
}  // namespace tessera
