#pragma once
/// Widens a float32 field to float64 on the device (host code calls it; widen_field.cu).
///
/// Why: on sm_90 with nvcc 13.0 the pixel kernel instantiated for float32 traced other paths
/// than the CPU (5% fewer lookups on the benchmarks' heat field, a biased image), while the
/// float64, int16, uint16 and uint8 instantiations reproduce the CPU's counters exactly
/// (docs/gpu.md, "Float32 fields"). A float32 value converts to double exactly, so the float64
/// kernel over the widened copy computes what the CPU computes over the float32 field.
#include <cstdint>

namespace tessera::cuda {

/// dst[i + nx * (j + ny * k)] = double(*(const float*)(src + i*s[0] + j*s[1] + k*s[2])) for
/// every element of dims; src and dst are device addresses. Launches on stream 0 and waits;
/// throws CudaError naming the kernel on a failure.
void widen_float32(const unsigned char* src, const std::int64_t dims[3], const std::int64_t byte_strides[3],
                   double* dst);

}  // namespace tessera::cuda
