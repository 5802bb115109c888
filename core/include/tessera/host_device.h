#pragma once
/// One source for host and device (pbrt-v4's PBRT_CPU_GPU): the per-sample code (camera rays,
/// sampling, tracking, the path tracer, lights, phase, BRDF, the grid medium and its field
/// lookups) is marked TESSERA_HOST_DEVICE, which is `__host__ __device__` under a CUDA
/// compiler and nothing otherwise, so a CPU-only build compiles exactly the plain C++ it
/// always did. The CUDA translation units (core/src/cuda/) include the same headers.
///
/// Constant tables that device code reads by a run-time index (the ziggurat's layers, the
/// Sobol' bytes) are declared once, for the host; TESSERA_DEVICE_TABLE(name) makes the
/// device's copy of `name` from the same initialiser at compile time (CUDA translation units
/// only), and TESSERA_TABLE(name) reads whichever copy the code is being compiled for.
#include <array>
#include <cstddef>

#if defined(__CUDACC__)
#define TESSERA_HOST_DEVICE __host__ __device__
#else
#define TESSERA_HOST_DEVICE
#endif

/// TESSERA_DEVICE_NOINLINE keeps a large function out of line in device code only: the GPU's
/// instruction cache holds one copy instead of one per call site, while the host compiler
/// still inlines as it chooses (the CPU's code does not change).
#if defined(__CUDA_ARCH__)
#define TESSERA_DEVICE_NOINLINE __noinline__
#else
#define TESSERA_DEVICE_NOINLINE
#endif

#if defined(__CUDA_ARCH__)
#define TESSERA_TABLE(name) name##_device
#else
#define TESSERA_TABLE(name) name
#endif

#if defined(__CUDACC__)
namespace tessera::detail {
/// A compile-time copy of a constant table as a std::array (the initialiser of its device copy).
template <class T, std::size_t N>
constexpr std::array<T, N> table_copy(const T (&a)[N]) {
  std::array<T, N> r{};
  for (std::size_t i = 0; i < N; ++i) r[i] = a[i];
  return r;
}
template <class T, std::size_t N>
constexpr std::array<T, N> table_copy(const std::array<T, N>& a) {
  return a;
}
}  // namespace tessera::detail
/// The device's copy of table `name` (internal linkage: each CUDA translation unit has its own).
#define TESSERA_DEVICE_TABLE(name) static __device__ constexpr auto name##_device = ::tessera::detail::table_copy(name)
#else
#define TESSERA_DEVICE_TABLE(name) static_assert(true)
#endif
