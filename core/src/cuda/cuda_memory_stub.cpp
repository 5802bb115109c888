/// cuda_copy_to_host (cuda_memory.h) in a build without CUDA: there is no device memory.
#include <tessera/cuda_memory.h>

#include <stdexcept>

namespace tessera {

void cuda_copy_to_host(void*, const void*, std::size_t, void*) {
  throw std::runtime_error("cuda_copy_to_host: Tessera was built without CUDA");
}

}  // namespace tessera
