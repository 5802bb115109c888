/// pixel_samples (pixel_kernel_impl.cuh) for: std::uint8_t.
#include "cuda/pixel_kernel_impl.cuh"

#include <cstdint>

TESSERA_PIXEL_KERNEL(std::uint8_t);
