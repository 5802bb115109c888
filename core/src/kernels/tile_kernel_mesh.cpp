/// The tile and preview kernels for a curvilinear or unstructured mesh (mesh.h): the field
/// lookups of kernel/mesh_medium.h, included before the kernels are instantiated.
#define TESSERA_EMULATED_SLICE_DEFINITION
#include "kernel/mesh_medium.h"
#include "kernels/emulated_slice.h"
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(MeshValue);
}  // namespace tessera

// The host emulation of the GPU backend's slices for the same Value (kernels/emulated_slice.h)
TESSERA_INSTANTIATE_EMULATED_SLICE(tessera::MeshValue);
