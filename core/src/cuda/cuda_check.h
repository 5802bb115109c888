#pragma once
/// CUDA errors as exceptions (host code of the CUDA backend only; never included by device
/// code; device memory is owned by BackendBuffer, device_backend.h). Every runtime call of the backend goes through
/// cuda_check, so a failure names the call and its arguments, the error's name and its text:
/// "CUDA: cudaMalloc(field copy, 8388608 bytes) failed: cudaErrorMemoryAllocation (out of memory)".
#include <cuda_runtime_api.h>

#include <cstddef>
#include <stdexcept>
#include <string>

namespace tessera::cuda {

/// Thrown for every failed CUDA runtime call of the backend, and for every call once the GPU
/// is disabled for the process (a sticky error, cuda_disabled in cuda_render.h).
class CudaError : public std::runtime_error {
 public:
  CudaError(const std::string& call, cudaError_t code)
      : std::runtime_error("CUDA: " + call + " failed: " + cudaGetErrorName(code) + " (" + cudaGetErrorString(code) +
                           ")"),
        m_code(code) {}
  /// A ready message (the GPU disabled for the process), with the error that disabled it.
  CudaError(cudaError_t code, const std::string& message) : std::runtime_error(message), m_code(code) {}
  cudaError_t code() const { return m_code; }

 private:
  cudaError_t m_code;
};

/// True for the errors after which the CUDA context is unusable (every later call of the
/// process fails with them): an illegal address or instruction, a kernel's launch failure or
/// trap, an uncorrectable ECC or NVLink error, a lost device.
bool is_sticky(cudaError_t e);

/// Records a sticky error `e` of `call` as the reason the GPU is disabled for the process
/// (the first one wins; later calls keep it).
void disable_gpu(cudaError_t e, const std::string& call);

/// Throws CudaError saying that the GPU was disabled for the process, and by which error and
/// call, if it was; else nothing. Every entry of the backend calls it first.
void throw_if_disabled();

/// Throws CudaError naming `call` unless `e` is cudaSuccess; a sticky error also disables the
/// GPU for the process.
inline void cuda_check(cudaError_t e, const std::string& call) {
  if (e == cudaSuccess) return;
  if (is_sticky(e)) disable_gpu(e, call);
  throw CudaError(call, e);
}

/// Makes `device` current for the object's life and restores the previous device after
/// (errors ignored on the way out: used in destructors and on unwinding).
class DeviceGuard {
 public:
  explicit DeviceGuard(int device) {
    if (cudaGetDevice(&m_prev) != cudaSuccess) m_prev = -1;
    if (m_prev != device) cudaSetDevice(device);
  }
  ~DeviceGuard() {
    if (m_prev >= 0) cudaSetDevice(m_prev);
  }
  DeviceGuard(const DeviceGuard&) = delete;
  DeviceGuard& operator=(const DeviceGuard&) = delete;

 private:
  int m_prev = -1;
};

}  // namespace tessera::cuda
