/// The CUDA backend's entry in a build without CUDA (TESSERA_CUDA=OFF, or no nvcc found):
/// no device, every pointer is host memory, the GPU is never disabled, render_tiles_cuda says
/// why it cannot run and cuda_field_summary summarises on the host. While a host emulation of
/// a GPU is installed (tests: gpu_emulation.h) the entries use it instead.
#include <tessera/cuda_render.h>

#include "cuda/emulated_device.h"

#include "cuda/gpu_emulation.h"
#include "cuda/mesh_device.h"

#include <stdexcept>

namespace tessera {

namespace {
constexpr const char* kNoCuda = "Tessera was built without CUDA (TESSERA_CUDA=OFF, or no nvcc found at configure time)";
}

bool cuda_built() { return cuda::gpu_emulation() != nullptr; }

int cuda_device_count(std::string* why) {
  if (cuda::gpu_emulation()) return 1;
  if (why) *why = kNoCuda;
  return 0;
}

MemoryKind cuda_memory_kind(const void* p) {
  const auto e = cuda::gpu_emulation();
  return e ? e->memory_kind(p) : MemoryKind::Host;
}

bool cuda_disabled(std::string*) { return false; }

void render_tiles_cuda(const PreparedScene& scene, std::span<const int> tile_indices, Film& film, RenderStats& stats,
                       const CudaLaunch& launch, CudaTransfer* transfer) {
  if (const auto e = cuda::gpu_emulation())
    return cuda::render_tiles_emulated(e, scene, tile_indices, film, stats, launch, transfer);
  throw std::runtime_error(std::string("render_tiles_cuda: ") + kNoCuda);
}

std::shared_ptr<const FieldSummary> cuda_field_summary(const FieldView& field, int edge, void*) {
  // Without CUDA every pointer the process can read is host memory (an emulated GPU's too)
  if (const auto e = cuda::gpu_emulation()) cuda::emulated_copy_out(*e, field.data, "cuda_field_summary");
  return FieldSummary::build(field, edge);
}

void cuda_field_summary_accumulate(FieldSummary::Parts& parts, const FieldView& block, const std::int64_t offset[3],
                                   const std::int64_t global_dims[3], int edge, void*) {
  if (const auto e = cuda::gpu_emulation()) cuda::emulated_copy_out(*e, block.data, "cuda_field_summary_accumulate");
  FieldSummary::accumulate(parts, block, offset, global_dims, edge);  // host memory, as above
}

namespace cuda {

// A mesh in device memory: only an emulated GPU's "device memory" can be read here
namespace {
void require_emulation(const char* what) {
  if (!gpu_emulation()) throw std::runtime_error(std::string(what) + ": " + kNoCuda);
}
}  // namespace

MeshIndexFault mesh_index_fault(const Mesh& mesh, void*) {
  require_emulation("checking a mesh in device memory");
  return mesh_index_fault_host(mesh);
}

MeshValueStats mesh_value_stats(const Mesh& mesh, void*) {
  require_emulation("the values of a mesh in device memory");
  return mesh_value_stats_host(mesh);
}

FieldSummary::Parts mesh_summary_cells(const Mesh& mesh, const MacroGrid& g, void*) {
  require_emulation("summarising a mesh in device memory");
  return mesh_summary_cells_host(mesh, g);
}

GeometrySums mesh_geometry_sums(const Mesh& mesh, void*) {
  require_emulation("hashing a mesh in device memory");
  return mesh_geometry_sums_host(mesh);
}

}  // namespace cuda
}  // namespace tessera
