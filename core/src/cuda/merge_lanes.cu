/// merge_lanes (pixel_kernel.h): each pixel's lane sums added to its sums in lane order.
#include "cuda/cuda_check.h"
#include "cuda/pixel_kernel.h"

#include <cuda_runtime.h>

#include <string>

namespace tessera::cuda {
namespace {

__global__ void merge(PixelSums* px, AuxSums* aux, const PixelSums* lane_px, const AuxSums* lane_aux,
                      std::int64_t njobs, int lanes) {
  const std::int64_t j = static_cast<std::int64_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (j >= njobs) return;
  PixelSums p = px[j];
  for (int l = 0; l < lanes; ++l) {
    const PixelSums& q = lane_px[j * lanes + l];
    p.r += q.r;
    p.g += q.g;
    p.b += q.b;
    p.a += q.a;
    p.lum += q.lum;
    p.lum2 += q.lum2;
    p.n += q.n;
    p.drawn += q.drawn;
  }
  px[j] = p;
  if (!aux) return;
  AuxSums x = aux[j];
  for (int l = 0; l < lanes; ++l)
    for (int c = 0; c < 3; ++c) {
      x.albedo[c] += lane_aux[j * lanes + l].albedo[c];
      x.normal[c] += lane_aux[j * lanes + l].normal[c];
    }
  aux[j] = x;
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
