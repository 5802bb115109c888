/// The tile and preview kernels for a hierarchy of refinement levels of any dtype (amr.h).
#define TESSERA_EMULATED_SLICE_DEFINITION
#include "kernels/emulated_slice.h"
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(AmrValue);
}  // namespace tessera

// The host emulation of the GPU backend's slices for the same Values (kernels/emulated_slice.h)
TESSERA_INSTANTIATE_EMULATED_SLICE(tessera::AmrValue);
