/// pixel_samples (pixel_kernel_impl.cuh) for: Rectilinear<float>,Rectilinear<double>.
#include "cuda/pixel_kernel_impl.cuh"

#include <cstdint>

TESSERA_PIXEL_KERNEL(tessera::Rectilinear<float>);
TESSERA_PIXEL_KERNEL(tessera::Rectilinear<double>);
