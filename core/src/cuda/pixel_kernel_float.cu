/// pixel_samples (pixel_kernel_impl.cuh) for: float,double.
#include "cuda/pixel_kernel_impl.cuh"

#include <cstdint>

TESSERA_PIXEL_KERNEL(float);
TESSERA_PIXEL_KERNEL(double);
