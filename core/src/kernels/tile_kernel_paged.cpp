/// The tile and preview kernels for a demand-paged field of any dtype (brick_cache.h).
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(PagedValue);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<PagedValue>);
}  // namespace tessera
