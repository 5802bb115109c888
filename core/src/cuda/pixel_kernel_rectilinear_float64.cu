/// pixel_samples (pixel_kernel_impl.cuh) for: Rectilinear<double> (float32 fields too,
/// widened, widen_field.h).
#include "cuda/pixel_kernel_impl.cuh"

TESSERA_PIXEL_KERNEL(tessera::Rectilinear<double>);
