/// The tile and preview kernels for the magnitude of a vector's three components of any
/// dtypes (magnitude_field.h), on uniform and rectilinear axes.
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(MagnitudeValue);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<MagnitudeValue>);
}  // namespace tessera
