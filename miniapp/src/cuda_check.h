#pragma once
/// cuda_check: a failing CUDA runtime call as a std::runtime_error that names the call, the
/// error's name and its text. For the miniapp's CUDA translation units only (it includes
/// <cuda_runtime.h>).
#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

namespace heat {

/// "cudaErrorNoDevice (no CUDA-capable device is detected)"
inline std::string cuda_error_text(cudaError_t e) {
  return std::string(cudaGetErrorName(e)) + " (" + cudaGetErrorString(e) + ")";
}

/// Throws std::runtime_error("CUDA: <call>: <name> (<text>)") unless e is cudaSuccess.
inline void cuda_check(cudaError_t e, const char* call) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("CUDA: ") + call + ": " + cuda_error_text(e));
}

}  // namespace heat
