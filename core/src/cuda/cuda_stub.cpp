/// The CUDA backend's entry in a build without CUDA (TESSERA_CUDA=OFF, or no nvcc found):
/// no device, and render_tiles_cuda says why it cannot run.
#include <tessera/cuda_render.h>

#include <stdexcept>

namespace tessera {

namespace {
constexpr const char* kNoCuda = "Tessera was built without CUDA (TESSERA_CUDA=OFF, or no nvcc found at configure time)";
}

bool cuda_built() { return false; }

int cuda_device_count(std::string* why) {
  if (why) *why = kNoCuda;
  return 0;
}

void render_tiles_cuda(const PreparedScene&, std::span<const int>, Film&, RenderStats&, const CudaLaunch&,
                       CudaTransfer*) {
  throw std::runtime_error(std::string("render_tiles_cuda: ") + kNoCuda);
}

}  // namespace tessera
