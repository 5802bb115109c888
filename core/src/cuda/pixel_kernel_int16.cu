/// pixel_samples (pixel_kernel_impl.cuh) for: std::int16_t.
#include "cuda/pixel_kernel_impl.cuh"

#include <cstdint>

TESSERA_PIXEL_KERNEL(std::int16_t);
