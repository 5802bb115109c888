/// The process-wide record of a sticky CUDA error (cuda_check.h): once a call of the backend
/// returns one, the CUDA context is unusable for the rest of the process, and every later
/// call of the backend throws at once, naming the error and the call that met it.
#include "cuda/cuda_check.h"

#include <tessera/cuda_render.h>

#include <atomic>
#include <mutex>

namespace tessera::cuda {

namespace {
std::atomic<bool> g_disabled{false};
std::mutex g_mutex;  // guards g_code and g_why
cudaError_t g_code = cudaSuccess;
std::string g_why;
}  // namespace

bool is_sticky(cudaError_t e) {
  switch (e) {
    case cudaErrorIllegalAddress:
    case cudaErrorLaunchFailure:
    case cudaErrorHardwareStackError:
    case cudaErrorIllegalInstruction:
    case cudaErrorMisalignedAddress:
    case cudaErrorInvalidAddressSpace:
    case cudaErrorInvalidPc:
    case cudaErrorECCUncorrectable:
    case cudaErrorLaunchTimeout:
    case cudaErrorAssert:
    case cudaErrorNvlinkUncorrectable:
    case cudaErrorExternalDevice:
    case cudaErrorContextIsDestroyed:
    case cudaErrorTensorMemoryLeak:
    case cudaErrorUnknown: return true;
    default: return false;
  }
}

void disable_gpu(cudaError_t e, const std::string& call) {
  const std::lock_guard lock(g_mutex);
  if (g_disabled.load()) return;
  g_code = e;
  g_why = std::string(cudaGetErrorName(e)) + " (" + cudaGetErrorString(e) + ") in " + call;
  g_disabled.store(true);
}

void throw_if_disabled() {
  if (!g_disabled.load()) return;
  const std::lock_guard lock(g_mutex);
  throw CudaError(g_code, "CUDA: the GPU was disabled for the process by " + g_why +
                              "; the CUDA context is unusable until the process restarts (render on the CPU)");
}

}  // namespace tessera::cuda

namespace tessera {

bool cuda_disabled(std::string* why) {
  if (!cuda::g_disabled.load()) return false;
  if (why) {
    const std::lock_guard lock(cuda::g_mutex);
    *why = cuda::g_why;
  }
  return true;
}

}  // namespace tessera
