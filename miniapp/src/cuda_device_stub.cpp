// tessera-heat without the CUDA backend (TESSERA_CUDA_ENABLED off): --device cuda is refused
// before the run starts, saying why (cuda_device.h).
#include "cuda_device.h"

#include <stdexcept>

namespace heat {

bool cuda_built() { return false; }

CudaDeviceChoice select_cuda_device(MPI_Comm /*comm*/) {
  CudaDeviceChoice c;
  c.error = "this tessera-heat was built without CUDA (configure Tessera with -DTESSERA_CUDA=ON and nvcc on PATH); "
            "use --device cpu";
  return c;
}

std::unique_ptr<HeatSimulation> make_cuda_solver(const CartDecomposition& /*decomp*/, const HeatParams& /*params*/) {
  throw std::logic_error("the CUDA heat solver is not in this build (built without CUDA)");
}

}  // namespace heat
