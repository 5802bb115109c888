/// The tile and preview kernels for a demand-paged field of any dtype (brick_cache.h), and the
/// host emulation's slice of the GPU kernel for it (every vertex through the device's bricks).
#define TESSERA_EMULATED_SLICE_DEFINITION
#include "kernels/emulated_slice.h"
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(PagedValue);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<PagedValue>);
}  // namespace tessera

TESSERA_INSTANTIATE_EMULATED_SLICE(tessera::PagedValue);
TESSERA_INSTANTIATE_EMULATED_SLICE(tessera::Rectilinear<tessera::PagedValue>);
