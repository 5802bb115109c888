/// cuda_copy_to_host and cuda_copy_box_to_host (cuda_memory.h) in a build without CUDA: there is no device memory (but
/// for an emulated GPU's, gpu_emulation.h).
#include <tessera/cuda_memory.h>

#include "cuda/box_gather.h"
#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"
#include "cuda/replica_host.h"

#include <cstring>
#include <stdexcept>

namespace tessera {

void cuda_copy_to_host(void* dst, const void* src, std::size_t bytes, void*) {
  if (cuda::gpu_emulation()) {  // an emulated GPU's device memory is host memory (tests)
    if (bytes) std::memcpy(dst, src, bytes);
    return;
  }
  throw std::runtime_error("cuda_copy_to_host: Tessera was built without CUDA");
}

void cuda_copy_box_to_host(void* dst, const FieldView& box, void*) {
  // Without CUDA every pointer the process can read is host memory (an emulated GPU's too)
  box.validate("box");
  if (const auto e = cuda::gpu_emulation()) cuda::emulated_copy_out(*e, box.data, "cuda_copy_box_to_host");
  cuda::gather_box(dst, box);
}

}  // namespace tessera

namespace tessera {

DeviceReplica cuda_assemble_on_device(std::span<const FieldView> blocks,
                                      std::span<const std::array<std::int64_t, 3>> offsets,
                                      const std::int64_t global[3], DType dtype, void*, std::uint64_t limit_bytes,
                                      const std::string& limit_text) {
  if (const auto e = cuda::gpu_emulation())
    return cuda::assemble_emulated(e, blocks, offsets, global, dtype, limit_bytes, limit_text);
  throw std::runtime_error("cuda_assemble_on_device: Tessera was built without CUDA");
}

}  // namespace tessera
