/// pixel_samples (pixel_kernel_impl.cuh) for refinement levels (AmrValue): built only with
/// -DTESSERA_CUDA_AMR=ON, until the kernel is known right on a GPU (docs/gpu.md).
#include "cuda/pixel_kernel_impl.cuh"

TESSERA_PIXEL_KERNEL(tessera::AmrValue);
