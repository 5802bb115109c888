/// pixel_samples (pixel_kernel_impl.cuh) for: MagnitudeValue,Rectilinear<MagnitudeValue>.
#include "cuda/pixel_kernel_impl.cuh"

#include <cstdint>

TESSERA_PIXEL_KERNEL(tessera::MagnitudeValue);
TESSERA_PIXEL_KERNEL(tessera::Rectilinear<tessera::MagnitudeValue>);
