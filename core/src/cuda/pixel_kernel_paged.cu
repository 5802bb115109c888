/// pixel_samples (pixel_kernel_impl.cuh) for a distributed (paged) field, uniform and with
/// rectilinear axes: every vertex through the device's bricks (device_bricks.h), its dtype
/// read per load.
#include "cuda/pixel_kernel_impl.cuh"

TESSERA_PIXEL_KERNEL(tessera::PagedValue);
TESSERA_PIXEL_KERNEL(tessera::Rectilinear<tessera::PagedValue>);
