/// cuda_copy_to_host (cuda_memory.h) in a CUDA build.
#include <tessera/cuda_memory.h>

#include "cuda/cuda_check.h"
#include "cuda/gpu_emulation.h"

#include <cstring>

#include <string>

namespace tessera {

void cuda_copy_to_host(void* dst, const void* src, std::size_t bytes, void* stream) {
  using cuda::cuda_check;
  if (cuda::gpu_emulation()) {  // an emulated GPU's device memory is host memory (tests)
    if (bytes) std::memcpy(dst, src, bytes);
    return;
  }
  cuda::throw_if_disabled();
  if (bytes == 0) return;
  const auto s = static_cast<cudaStream_t>(stream);
  if (s) cuda_check(cudaStreamSynchronize(s), "cudaStreamSynchronize(the simulation's stream)");
  else cuda_check(cudaDeviceSynchronize(), "cudaDeviceSynchronize");
  cuda_check(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToHost),
             "cudaMemcpy(" + std::to_string(bytes) + " bytes of a device array to the host)");
}

}  // namespace tessera
