/// The tile and preview kernels for the magnitude of a vector's three components of any
/// dtypes (magnitude_field.h), on uniform and rectilinear axes.
#define TESSERA_EMULATED_SLICE_DEFINITION
#include "kernels/emulated_slice.h"
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(MagnitudeValue);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<MagnitudeValue>);
}  // namespace tessera

// The host emulation of the GPU backend's slices for the same Values (kernels/emulated_slice.h)
TESSERA_INSTANTIATE_EMULATED_SLICE(tessera::MagnitudeValue);
TESSERA_INSTANTIATE_EMULATED_SLICE(tessera::Rectilinear<tessera::MagnitudeValue>);
