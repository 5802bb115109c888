/// pixel_samples (pixel_kernel_impl.cuh) for: double (float32 fields too: they are widened to
/// a float64 copy on the device, widen_field.h).
#include "cuda/pixel_kernel_impl.cuh"

TESSERA_PIXEL_KERNEL(double);
