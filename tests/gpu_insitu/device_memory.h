#pragma once
// Device memory for the adapter's device tests: cudaMalloc'd on a GPU
// (tessera_gpu_insitu_tests), or, with TESSERA_GPU_TESTS_EMULATED, host memory declared
// device memory of the host emulation of a GPU that emulated_main.cpp installs
// (tessera_emulated_insitu_tests, every build: core/src/cuda/gpu_emulation.h).
#include <catch2/catch.hpp>

#include <cstddef>
#include <cstring>

#if defined(TESSERA_GPU_TESTS_EMULATED)
#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"

#include <new>
#else
#include <cuda_runtime_api.h>
#endif

namespace device_test {

inline void* alloc(std::size_t bytes) {
#if defined(TESSERA_GPU_TESTS_EMULATED)
  void* p = ::operator new(bytes);
  tessera::cuda::emulated_declare_device_memory(*tessera::cuda::gpu_emulation(), p, bytes);
  return p;
#else
  void* p = nullptr;
  REQUIRE(cudaMalloc(&p, bytes) == cudaSuccess);
  return p;
#endif
}

inline void release(void* p) {
#if defined(TESSERA_GPU_TESTS_EMULATED)
  tessera::cuda::emulated_forget_device_memory(*tessera::cuda::gpu_emulation(), p);
  ::operator delete(p);
#else
  cudaFree(p);
#endif
}

/// A stream of the simulation's (a cudaStream_t; a dummy handle on the emulated GPU, which
/// has nothing queued).
inline void* make_stream() {
#if defined(TESSERA_GPU_TESTS_EMULATED)
  static int dummy;
  return &dummy;
#else
  cudaStream_t s;
  REQUIRE(cudaStreamCreate(&s) == cudaSuccess);
  return s;
#endif
}

inline void destroy_stream(void* s) {
#if !defined(TESSERA_GPU_TESTS_EMULATED)
  cudaStreamDestroy(static_cast<cudaStream_t>(s));
#else
  (void)s;
#endif
}

/// Copies host bytes to device memory, queued on `stream` when given.
inline void upload(void* dst, const void* src, std::size_t bytes, void* stream = nullptr) {
#if defined(TESSERA_GPU_TESTS_EMULATED)
  (void)stream;
  std::memcpy(dst, src, bytes);
#else
  if (stream)
    REQUIRE(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyHostToDevice, static_cast<cudaStream_t>(stream)) == cudaSuccess);
  else REQUIRE(cudaMemcpy(dst, src, bytes, cudaMemcpyHostToDevice) == cudaSuccess);
#endif
}

}  // namespace device_test
