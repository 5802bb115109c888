/// pixel_samples (pixel_kernel_impl.cuh) for: std::uint16_t.
#include "cuda/pixel_kernel_impl.cuh"

#include <cstdint>

TESSERA_PIXEL_KERNEL(std::uint16_t);
