/// pixel_samples (pixel_kernel_impl.cuh) for: Rectilinear<std::uint8_t>,Rectilinear<std::int16_t>,Rectilinear<std::uint16_t>.
#include "cuda/pixel_kernel_impl.cuh"

#include <cstdint>

TESSERA_PIXEL_KERNEL(tessera::Rectilinear<std::uint8_t>);
TESSERA_PIXEL_KERNEL(tessera::Rectilinear<std::int16_t>);
TESSERA_PIXEL_KERNEL(tessera::Rectilinear<std::uint16_t>);
