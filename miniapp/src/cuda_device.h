#pragma once
/// tessera-heat --device cuda: the GPU each rank uses, and the solver on it.
///
/// Each rank uses one GPU: its node-local rank (MPI_Comm_split_type with
/// MPI_COMM_TYPE_SHARED) modulo the devices the CUDA runtime shows it (CUDA_VISIBLE_DEVICES
/// applies), the rule of the adapter's `tessera.cuda_device: -1`. Built with the CUDA backend
/// (TESSERA_CUDA_ENABLED) this is cuda_device.cu; otherwise cuda_device_stub.cpp, which refuses
/// with a message saying the build has no CUDA.
#include "cart_decomposition.h"
#include "heat_simulation.h"
#include "heat_solver.h"

#include <mpi.h>

#include <memory>
#include <string>

namespace heat {

/// True when tessera-heat was compiled with the CUDA solver.
bool cuda_built();

struct CudaDeviceChoice {
  int device = -1;     ///< the CUDA device index this rank uses; -1 with an error
  int visible = 0;     ///< devices visible to this rank
  int local_rank = 0;  ///< rank within this node (MPI_COMM_TYPE_SHARED)
  std::string name;    ///< the device's name (cudaDeviceProp::name)
  std::string error;   ///< why this rank has no device ("" when it has one)
};

/// Collective over `comm` (the node split). Selects the device (cudaSetDevice) for the calling
/// thread; never throws: a build without CUDA, no visible device or a failing CUDA call is an
/// `error` naming the CUDA error. The ranks do not agree here: the caller allreduces.
CudaDeviceChoice select_cuda_device(MPI_Comm comm);

/// A CudaHeatSolver (heat_solver_cuda.h) on the selected device. Collective over
/// decomp.comm(); throws what its constructor throws, and std::logic_error in a build without
/// CUDA.
std::unique_ptr<HeatSimulation> make_cuda_solver(const CartDecomposition& decomp, const HeatParams& params);

}  // namespace heat
