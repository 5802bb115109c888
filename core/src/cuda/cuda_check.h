#pragma once
/// CUDA errors as exceptions, and device memory owned by RAII (host code of the CUDA backend
/// only; never included by device code). Every runtime call of the backend goes through
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

/// One device allocation, freed when the object goes (a free's error is ignored there: the
/// error that unwound the render is the one reported).
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  DeviceBuffer(std::size_t bytes, const char* what) { allocate(bytes, what); }
  ~DeviceBuffer() {
    if (m_ptr) cudaFree(m_ptr);
  }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;

  void allocate(std::size_t bytes, const char* what) {
    if (m_ptr) cudaFree(m_ptr);
    m_ptr = nullptr;
    m_bytes = 0;
    cuda_check(cudaMalloc(&m_ptr, bytes > 0 ? bytes : 1),
               std::string("cudaMalloc(") + what + ", " + std::to_string(bytes) + " bytes)");
    m_bytes = bytes;
  }
  /// Allocates `bytes` and copies them from host memory `src`; returns the bytes copied.
  std::size_t upload(const void* src, std::size_t bytes, const char* what) {
    allocate(bytes, what);
    if (bytes > 0)
      cuda_check(cudaMemcpy(m_ptr, src, bytes, cudaMemcpyHostToDevice),
                 std::string("cudaMemcpy(") + what + " to the device, " + std::to_string(bytes) + " bytes)");
    return bytes;
  }
  void* get() const { return m_ptr; }
  template <class T>
  T* as() const {
    return static_cast<T*>(m_ptr);
  }
  std::size_t bytes() const { return m_bytes; }

 private:
  void* m_ptr = nullptr;
  std::size_t m_bytes = 0;
};

}  // namespace tessera::cuda
