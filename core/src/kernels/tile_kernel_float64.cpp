/// The tile and preview kernels for float64 fields (uniform, and with rectilinear axes).
#define TESSERA_EMULATED_SLICE_DEFINITION
#include "kernels/emulated_slice.h"
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(double);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<double>);
}  // namespace tessera

// The host emulation of the GPU backend's slices for the same Values (kernels/emulated_slice.h)
TESSERA_INSTANTIATE_EMULATED_SLICE(double);
TESSERA_INSTANTIATE_EMULATED_SLICE(tessera::Rectilinear<double>);
