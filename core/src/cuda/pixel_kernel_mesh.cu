/// pixel_samples (pixel_kernel_impl.cuh) for curvilinear and unstructured meshes (MeshValue:
/// the field lookups of kernel/mesh_medium.h, every value dtype read per load).
#include "cuda/pixel_kernel_impl.cuh"

TESSERA_PIXEL_KERNEL(tessera::MeshValue);
