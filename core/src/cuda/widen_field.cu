/// widen_float32 (widen_field.h).
#include "cuda/cuda_check.h"
#include "cuda/widen_field.h"

#include <cuda_runtime.h>

#include <string>

namespace tessera::cuda {
namespace {

__global__ void widen(const unsigned char* src, std::int64_t nx, std::int64_t ny, std::int64_t n, std::int64_t sx,
                      std::int64_t sy, std::int64_t sz, double* dst) {
  for (std::int64_t q = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; q < n;
       q += static_cast<std::int64_t>(gridDim.x) * blockDim.x) {
    const std::int64_t i = q % nx, j = (q / nx) % ny, k = q / (nx * ny);
    float v;
    __builtin_memcpy(&v, src + i * sx + j * sy + k * sz, sizeof v);
    dst[q] = static_cast<double>(v);
  }
}

}  // namespace

void widen_float32(const unsigned char* src, const std::int64_t dims[3], const std::int64_t byte_strides[3],
                   double* dst) {
  const std::int64_t n = dims[0] * dims[1] * dims[2];
  if (n <= 0) return;
  const std::int64_t blocks = std::min<std::int64_t>((n + 255) / 256, 65535);
  widen<<<static_cast<unsigned>(blocks), 256>>>(src, dims[0], dims[1], n, byte_strides[0], byte_strides[1],
                                                byte_strides[2], dst);
  cuda_check(cudaGetLastError(), "launch of widen (float32 field to float64, " + std::to_string(n) + " values)");
  cuda_check(cudaDeviceSynchronize(), "widen (float32 field to float64)");
}

}  // namespace tessera::cuda
