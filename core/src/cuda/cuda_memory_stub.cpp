/// cuda_copy_to_host and cuda_copy_box_to_host (cuda_memory.h) in a build without CUDA: there is no device memory (but
/// for an emulated GPU's, gpu_emulation.h).
#include <tessera/cuda_memory.h>

#include "cuda/box_gather.h"
#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"

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
