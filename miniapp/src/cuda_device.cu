// tessera-heat --device cuda with the CUDA backend: one GPU per rank, by node-local rank
// (cuda_device.h).
#include "cuda_check.h"
#include "cuda_device.h"
#include "heat_solver_cuda.h"

#include <cstdlib>

namespace heat {

bool cuda_built() { return true; }

CudaDeviceChoice select_cuda_device(MPI_Comm comm) {
  CudaDeviceChoice c;
  // The rank within this node: ranks sharing a node share its devices round robin
  MPI_Comm node = MPI_COMM_NULL;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  MPI_Comm_rank(node, &c.local_rank);
  MPI_Comm_free(&node);

  const char* env = std::getenv("CUDA_VISIBLE_DEVICES");
  const std::string visible = env ? "CUDA_VISIBLE_DEVICES=" + std::string(env) : "CUDA_VISIBLE_DEVICES unset";
  int count = 0;
  cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess || count <= 0) {
    c.error = "no CUDA device visible: cudaGetDeviceCount: " +
              (e != cudaSuccess ? cuda_error_text(e) : std::string("0 devices")) + "; " + visible;
    return c;
  }
  c.visible = count;
  const int device = c.local_rank % count;
  // Select it, and create its context now, so that a device that cannot be used fails here
  e = cudaSetDevice(device);
  if (e == cudaSuccess) e = cudaFree(nullptr);
  if (e != cudaSuccess) {
    c.error = "CUDA device " + std::to_string(device) + " of " + std::to_string(count) +
              " cannot be used: " + cuda_error_text(e) + "; " + visible;
    return c;
  }
  c.device = device;
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, device) == cudaSuccess) c.name = prop.name;
  return c;
}

std::unique_ptr<HeatSimulation> make_cuda_solver(const CartDecomposition& decomp, const HeatParams& params) {
  return std::make_unique<CudaHeatSolver>(decomp, params);
}

}  // namespace heat
