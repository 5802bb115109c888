/// The CUDA backend's entry in a build without CUDA (TESSERA_CUDA=OFF, or no nvcc found):
/// no device, every pointer is host memory, the GPU is never disabled, render_tiles_cuda says
/// why it cannot run and cuda_field_summary summarises on the host.
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

MemoryKind cuda_memory_kind(const void*) { return MemoryKind::Host; }

bool cuda_disabled(std::string*) { return false; }

void render_tiles_cuda(const PreparedScene&, std::span<const int>, Film&, RenderStats&, const CudaLaunch&,
                       CudaTransfer*) {
  throw std::runtime_error(std::string("render_tiles_cuda: ") + kNoCuda);
}

std::shared_ptr<const FieldSummary> cuda_field_summary(const FieldView& field, int edge, void*) {
  // Without CUDA every pointer the process can read is host memory
  return FieldSummary::build(field, edge);
}

}  // namespace tessera
