/// The tile and preview kernels for a hierarchy of refinement levels of any dtype (amr.h).
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(AmrValue);
}  // namespace tessera
