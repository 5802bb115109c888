/// merge_lanes (pixel_kernel.h): merge_pixel (lane_kernel.h) for every pixel, one thread each.
#include "cuda/cuda_check.h"
#include "kernels/lane_kernel.h"
#include "cuda/pixel_kernel.h"

#include <cuda_runtime.h>

#include <string>

namespace tessera::cuda {
namespace {

__global__ void merge(PixelSums* px, AuxSums* aux, const PixelSums* lane_px, const AuxSums* lane_aux,
                      std::int64_t njobs, int lanes) {
  const std::int64_t j = static_cast<std::int64_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (j < njobs) merge_pixel(px, aux, lane_px, lane_aux, j, lanes);
}

}  // namespace

void merge_lanes(PixelSums* px, AuxSums* aux, const PixelSums* lane_px, const AuxSums* lane_aux, std::int64_t njobs,
                 int lanes) {
  if (njobs <= 0) return;
  const auto blocks = static_cast<unsigned>((njobs + 127) / 128);
  merge<<<blocks, 128>>>(px, aux, lane_px, lane_aux, njobs, lanes);
  cuda_check(cudaGetLastError(), "launch of merge_lanes (" + std::to_string(njobs) + " pixels)");
  cuda_check(cudaDeviceSynchronize(), "merge_lanes (" + std::to_string(njobs) + " pixels, " + std::to_string(lanes) +
                                          " lanes)");
}

}  // namespace tessera::cuda
