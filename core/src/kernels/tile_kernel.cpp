/// The one dispatcher of the per-tile kernels: the field's Value picks the translation unit
/// (tile_kernel_<value>.cpp), which picks the mode combination (kernel_dispatch.h).
#include "kernels/tile_kernel.h"

#include "kernel/kernel_dispatch.h"
#include "kernels/tile_kernel_instances.h"

namespace tessera {

TileKernel tile_kernel(const KernelScene& ks) {
  return with_value(ks, [&](auto tag) { return tile_kernel_for<typename decltype(tag)::type>(ks); });
}

PreviewKernel preview_kernel(const KernelScene& ks) {
  return with_value(ks, [&](auto tag) { return preview_kernel_for<typename decltype(tag)::type>(ks); });
}

}  // namespace tessera
