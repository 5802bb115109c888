/// The tile and preview kernels for float32 fields (uniform, and with rectilinear axes).
#if defined(TESSERA_CUDA_FLOAT32)
#define TESSERA_EMULATED_SLICE_DEFINITION
#include "kernels/emulated_slice.h"
#endif
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(float);
TESSERA_INSTANTIATE_TILE_KERNELS(Rectilinear<float>);
}  // namespace tessera

#if defined(TESSERA_CUDA_FLOAT32)
// The host emulation of the float32 kernel (TESSERA_CUDA_FLOAT32, the default; else float32 fields are
// widened and drawn by the float64 slices)
TESSERA_INSTANTIATE_EMULATED_SLICE(float);
TESSERA_INSTANTIATE_EMULATED_SLICE(tessera::Rectilinear<float>);
#endif
