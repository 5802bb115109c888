/// pixel_samples (pixel_kernel_impl.cuh) for float32 fields read as they are, uniform and with
/// rectilinear axes: built with TESSERA_CUDA_FLOAT32 (on by default, docs/gpu.md); with
/// -DTESSERA_CUDA_FLOAT32=OFF a float32 field is widened to a float64 copy (widen_field.h)
/// and drawn by the float64 kernels.
#include "cuda/pixel_kernel_impl.cuh"

TESSERA_PIXEL_KERNEL(float);
TESSERA_PIXEL_KERNEL(tessera::Rectilinear<float>);
