/// The one dispatcher of the per-tile kernels: the field's Value (kernel_dispatch.h) picks the
/// kernels of its translation unit (tile_kernel_<value>.cpp).
#include "kernels/tile_kernel.h"

#include "kernel/kernel_dispatch.h"
#include "kernels/tile_kernel_instances.h"

namespace tessera {

TileKernel tile_kernel(const KernelScene& ks) {
  return with_value(ks, [&](auto tag) { return tile_kernel_for<typename decltype(tag)::type>(); });
}

PreviewKernel preview_kernel(const KernelScene& ks) {
  return with_value(ks, [&](auto tag) { return preview_kernel_for<typename decltype(tag)::type>(); });
}

}  // namespace tessera
