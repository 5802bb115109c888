/// cuda_copy_box_to_host and cuda_assemble_on_device (cuda_memory.h) in a CUDA build: one
/// kernel places a strided device box into another (one thread per element, any byte
/// strides): into a dense box to copy only its elements to the host, or into a replica.
#include <tessera/cuda_memory.h>
#include <tessera/cuda_render.h>

#include "cuda/box_gather.h"
#include "cuda/cuda_backend.h"
#include "cuda/cuda_check.h"
#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"
#include "cuda/replica_host.h"

#include <cuda_runtime.h>

#include <algorithm>
#include <stdexcept>
#include <cstdint>
#include <string>
#include <vector>

namespace tessera::cuda {
namespace {

/// Element q of a box of nx x ny x (n / nx / ny) elements at src (strides sx, sy, sz) to the
/// same element of the box at dst (strides dx, dy, dz), e bytes each.
__global__ void place_box(const unsigned char* src, std::int64_t nx, std::int64_t ny, std::int64_t n, std::int64_t sx,
                          std::int64_t sy, std::int64_t sz, std::int64_t e, unsigned char* dst, std::int64_t dx,
                          std::int64_t dy, std::int64_t dz) {
  for (std::int64_t q = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; q < n;
       q += static_cast<std::int64_t>(gridDim.x) * blockDim.x) {
    const std::int64_t i = q % nx, j = (q / nx) % ny, k = q / (nx * ny);
    const unsigned char* from = src + i * sx + j * sy + k * sz;
    unsigned char* to = dst + i * dx + j * dy + k * dz;
    for (std::int64_t b = 0; b < e; ++b) to[b] = from[b];
  }
}

}  // namespace
}  // namespace tessera::cuda

namespace tessera {

void cuda_copy_box_to_host(void* dst, const FieldView& box, void* stream) {
  using cuda::cuda_check;
  box.validate("box");
  if (const auto e = cuda::gpu_emulation()) {  // its device memory is host memory
    cuda::emulated_copy_out(*e, box.data, "cuda_copy_box_to_host");
    return cuda::gather_box(dst, box);
  }
  cuda::throw_if_disabled();
  const auto s = static_cast<cudaStream_t>(stream);
  const MemoryKind kind = cuda_memory_kind(box.data);
  if (kind == MemoryKind::Host) return cuda::gather_box(dst, box);
  cudaPointerAttributes attr{};
  cuda_check(cudaPointerGetAttributes(&attr, box.data), "cudaPointerGetAttributes(box)");
  const cuda::DeviceGuard guard(attr.device >= 0 ? attr.device : 0);
  if (s) cuda_check(cudaStreamSynchronize(s), "cudaStreamSynchronize(the simulation's stream)");
  else cuda_check(cudaDeviceSynchronize(), "cudaDeviceSynchronize");
  if (kind == MemoryKind::Managed) return cuda::gather_box(dst, box);  // readable on the host now
  const std::int64_t n = box.vertex_count();
  const auto e = static_cast<std::int64_t>(dtype_size(box.dtype));
  const auto bytes = static_cast<std::size_t>(n * e);
  cuda::BackendBuffer packed(*cuda::cuda_backend(attr.device >= 0 ? attr.device : 0));
  packed.allocate(bytes, "a device box packed for the host");
  const auto blocks = static_cast<unsigned>(std::clamp<std::int64_t>((n + 255) / 256, 1, 65535));
  // Packed: placed into a dense box of the same dims
  cuda::place_box<<<blocks, 256>>>(static_cast<const unsigned char*>(box.data), box.dims[0], box.dims[1], n,
                                   box.byte_strides[0], box.byte_strides[1], box.byte_strides[2], e,
                                   packed.as<unsigned char>(), e, e * box.dims[0], e * box.dims[0] * box.dims[1]);
  cuda_check(cudaGetLastError(), "launch of place_box (" + std::to_string(n) + " elements packed)");
  cuda_check(cudaDeviceSynchronize(), "place_box (a device box packed for the host)");
  cuda_check(cudaMemcpy(dst, packed.get(), bytes, cudaMemcpyDeviceToHost),
             "cudaMemcpy(" + std::to_string(bytes) + " bytes of a device box to the host)");
}

DeviceReplica cuda_assemble_on_device(std::span<const FieldView> blocks,
                                      std::span<const std::array<std::int64_t, 3>> offsets,
                                      const std::int64_t global[3], DType dtype, void* stream,
                                      std::uint64_t limit_bytes, const std::string& limit_text) {
  using cuda::cuda_check;
  if (const auto e = cuda::gpu_emulation())
    return cuda::assemble_emulated(e, blocks, offsets, global, dtype, limit_bytes, limit_text);
  cuda::throw_if_disabled();
  const std::size_t bytes = cuda::replica_bytes(blocks.size(), offsets.size(), global, dtype, limit_bytes, limit_text);
  // Where each block is: device memory of one device (the replica's), managed (read there as
  // it is), or the host's
  int device = -1;
  std::vector<char> on_host(blocks.size(), 0);
  for (std::size_t n = 0; n < blocks.size(); ++n) {
    cudaPointerAttributes attr{};
    cuda_check(cudaPointerGetAttributes(&attr, blocks[n].data), "cudaPointerGetAttributes(block)");
    if (attr.type == cudaMemoryTypeDevice) {
      if (device >= 0 && attr.device != device)
        throw std::invalid_argument("cuda_assemble_on_device: the blocks are device memory of two devices");
      device = attr.device;
    }
    on_host[n] = attr.type != cudaMemoryTypeDevice && attr.type != cudaMemoryTypeManaged;
  }
  if (device < 0) throw std::invalid_argument("cuda_assemble_on_device: no block is device memory");
  const cuda::DeviceGuard guard(device);
  const auto s = static_cast<cudaStream_t>(stream);
  if (s) cuda_check(cudaStreamSynchronize(s), "cudaStreamSynchronize(the simulation's stream)");
  else cuda_check(cudaDeviceSynchronize(), "cudaDeviceSynchronize");
  void* raw = nullptr;
  cuda_check(cudaMalloc(&raw, bytes), "cudaMalloc(" + std::to_string(bytes) + " bytes: the field assembled on the device)");
  std::shared_ptr<const void> memory(raw, [device](const void* p) {
    int prev = 0;
    if (cudaGetDevice(&prev) != cudaSuccess) prev = device;
    cudaSetDevice(device);
    cudaFree(const_cast<void*>(p));  // nothing to do about a failure here
    cudaSetDevice(prev);
  });
  const FieldView dst = FieldView::contiguous(raw, dtype, global[0], global[1], global[2]);
  const auto e = static_cast<std::int64_t>(dtype_size(dtype));
  std::uint64_t from_host = 0;
  std::vector<unsigned char> packed;  // a host block whose rows are not x-contiguous, packed
  for (std::size_t n = 0; n < blocks.size(); ++n) {
    const FieldView& b = blocks[n];
    const std::int64_t count = b.vertex_count();
    auto* to = static_cast<unsigned char*>(raw) + offsets[n][0] * dst.byte_strides[0] +
               offsets[n][1] * dst.byte_strides[1] + offsets[n][2] * dst.byte_strides[2];
    if (on_host[n]) {
      // Its rows to their places: straight from the block when its rows are x-contiguous and
      // its planes a whole number of rows apart (a dense or ghosted array), else packed first
      const std::int64_t* bs = b.byte_strides;
      const bool pitched = bs[0] == e && bs[1] >= e * b.dims[0] && bs[2] > 0 && bs[2] % bs[1] == 0 &&
                           bs[2] / bs[1] >= b.dims[1];
      cudaMemcpy3DParms p{};
      if (pitched) {
        p.srcPtr = make_cudaPitchedPtr(const_cast<void*>(b.data), static_cast<std::size_t>(bs[1]),
                                       static_cast<std::size_t>(e * b.dims[0]), static_cast<std::size_t>(bs[2] / bs[1]));
      } else {
        packed.resize(static_cast<std::size_t>(count * e));
        copy_box(b, packed.data(), FieldView::contiguous(packed.data(), dtype, b.dims[0], b.dims[1], b.dims[2]).byte_strides);
        p.srcPtr = make_cudaPitchedPtr(packed.data(), static_cast<std::size_t>(e * b.dims[0]),
                                       static_cast<std::size_t>(e * b.dims[0]), static_cast<std::size_t>(b.dims[1]));
      }
      p.dstPtr = make_cudaPitchedPtr(raw, static_cast<std::size_t>(dst.byte_strides[1]),
                                     static_cast<std::size_t>(dst.byte_strides[1]), static_cast<std::size_t>(global[1]));
      p.dstPos = make_cudaPos(static_cast<std::size_t>(offsets[n][0] * e), static_cast<std::size_t>(offsets[n][1]),
                              static_cast<std::size_t>(offsets[n][2]));
      p.extent = make_cudaExtent(static_cast<std::size_t>(e * b.dims[0]), static_cast<std::size_t>(b.dims[1]),
                                 static_cast<std::size_t>(b.dims[2]));
      p.kind = cudaMemcpyHostToDevice;
      cuda_check(cudaMemcpy3D(&p), "cudaMemcpy3D(a host block of " + std::to_string(count) +
                                       " elements into the field assembled on the device)");
      from_host += static_cast<std::uint64_t>(count * e);
      continue;
    }
    const auto grid = static_cast<unsigned>(std::clamp<std::int64_t>((count + 255) / 256, 1, 65535));
    cuda::place_box<<<grid, 256>>>(static_cast<const unsigned char*>(b.data), b.dims[0], b.dims[1], count,
                                   b.byte_strides[0], b.byte_strides[1], b.byte_strides[2], e, to,
                                   dst.byte_strides[0], dst.byte_strides[1], dst.byte_strides[2]);
    cuda_check(cudaGetLastError(), "launch of place_box (" + std::to_string(count) + " elements)");
  }
  cuda_check(cudaDeviceSynchronize(), "place_box (the field assembled on the device)");
  return DeviceReplica{std::move(memory), dst, from_host};
}

}  // namespace tessera
