/// The tile and preview kernels for a curvilinear or unstructured mesh (mesh.h): the field
/// lookups of kernel/mesh_medium.h, included before the kernels are instantiated.
#include "kernel/mesh_medium.h"
#include "kernels/tile_kernel_impl.h"

namespace tessera {
TESSERA_INSTANTIATE_TILE_KERNELS(MeshValue);
}  // namespace tessera
