#include "cuda_check.h"
#include "halo_exchange_cuda.h"

#include <mpi.h>

#include <algorithm>

namespace heat {
namespace {

/// One layer of the array across axis `a`: layer index `layer` along a, the other two axes
/// b < c in full; buffer element v * extent_b + u holds array element (u along b, v along c).
struct FaceView {
  std::int64_t offset;  ///< layer * stride[a]
  std::int64_t stride_b, stride_c;
  std::int64_t extent_b, extent_c;
};

FaceView face_view(const Index3& dims, int a, std::int64_t layer) {
  const std::int64_t stride[3] = {1, dims[0], dims[0] * dims[1]};
  const int b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
  return {layer * stride[a], stride[b], stride[c], dims[b], dims[c]};
}

__global__ void pack_face(const double* __restrict__ field, double* __restrict__ buffer, FaceView f) {
  const std::int64_t count = f.extent_b * f.extent_c;
  for (std::int64_t e = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; e < count;
       e += static_cast<std::int64_t>(gridDim.x) * blockDim.x) {
    const std::int64_t u = e % f.extent_b, v = e / f.extent_b;
    buffer[e] = field[f.offset + u * f.stride_b + v * f.stride_c];
  }
}

__global__ void unpack_face(double* __restrict__ field, const double* __restrict__ buffer, FaceView f) {
  const std::int64_t count = f.extent_b * f.extent_c;
  for (std::int64_t e = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; e < count;
       e += static_cast<std::int64_t>(gridDim.x) * blockDim.x) {
    const std::int64_t u = e % f.extent_b, v = e / f.extent_b;
    field[f.offset + u * f.stride_b + v * f.stride_c] = buffer[e];
  }
}

constexpr int kBlock = 256;

unsigned blocks_for(std::int64_t count) {
  return static_cast<unsigned>(std::clamp<std::int64_t>((count + kBlock - 1) / kBlock, 1, 4096));
}

}  // namespace

CudaHaloExchange::CudaHaloExchange(const CartDecomposition& decomp, CUstream_st* stream)
    : m_decomp(decomp), m_stream(stream) {
  const Index3& n = decomp.owned();
  for (int a = 0; a < 3; ++a) m_dims[a] = n[a] + 2;
  std::size_t largest = 0;
  for (int a = 0; a < 3; ++a) {
    const FaceView f = face_view(m_dims, a, 0);
    const std::size_t face = static_cast<std::size_t>(f.extent_b * f.extent_c);
    for (int dir : {-1, 1})
      if (decomp.neighbor(a, dir) != MPI_PROC_NULL) {
        m_bytes += face * sizeof(double);
        largest = std::max(largest, face);
      }
  }
  if (largest == 0) return;  // one rank: no neighbours, nothing to move
  try {
    for (int b = 0; b < 4; ++b) {
      cuda_check(cudaMalloc(&m_device[b], largest * sizeof(double)), "cudaMalloc (halo face)");
      cuda_check(cudaMallocHost(&m_host[b], largest * sizeof(double)), "cudaMallocHost (halo face)");
    }
  } catch (...) {
    release();
    throw;
  }
}

CudaHaloExchange::~CudaHaloExchange() { release(); }

void CudaHaloExchange::release() noexcept {
  for (int b = 0; b < 4; ++b) {
    if (m_device[b]) cudaFree(m_device[b]);
    if (m_host[b]) cudaFreeHost(m_host[b]);
    m_device[b] = m_host[b] = nullptr;
  }
}

void CudaHaloExchange::exchange(double* field) {
  enum { kSendLo, kSendHi, kRecvLo, kRecvHi };
  const MPI_Comm comm = m_decomp.comm();
  const Index3& n = m_decomp.owned();
  cudaStream_t s = m_stream;
  for (int a = 0; a < 3; ++a) {
    const int lo = m_decomp.neighbor(a, -1), hi = m_decomp.neighbor(a, +1);
    if (lo == MPI_PROC_NULL && hi == MPI_PROC_NULL) continue;
    // Layer positions along the axis: ghost at 0, owned 1..n, ghost n+1
    const FaceView first = face_view(m_dims, a, 1), last = face_view(m_dims, a, n[a]);
    const FaceView ghost_lo = face_view(m_dims, a, 0), ghost_hi = face_view(m_dims, a, n[a] + 1);
    const std::int64_t count = first.extent_b * first.extent_c;
    const std::size_t bytes = static_cast<std::size_t>(count) * sizeof(double);

    // Pack the owned layers next to the neighbours and bring them to the host
    if (hi != MPI_PROC_NULL) {
      pack_face<<<blocks_for(count), kBlock, 0, s>>>(field, m_device[kSendHi], last);
      cuda_check(cudaGetLastError(), "pack_face launch");
      cuda_check(cudaMemcpyAsync(m_host[kSendHi], m_device[kSendHi], bytes, cudaMemcpyDeviceToHost, s),
                 "cudaMemcpyAsync (halo face to host)");
    }
    if (lo != MPI_PROC_NULL) {
      pack_face<<<blocks_for(count), kBlock, 0, s>>>(field, m_device[kSendLo], first);
      cuda_check(cudaGetLastError(), "pack_face launch");
      cuda_check(cudaMemcpyAsync(m_host[kSendLo], m_device[kSendLo], bytes, cudaMemcpyDeviceToHost, s),
                 "cudaMemcpyAsync (halo face to host)");
    }
    cuda_check(cudaStreamSynchronize(s), "cudaStreamSynchronize (halo faces packed)");

    // Last owned layer up, low ghost layer filled from below; then the reverse (HaloExchange)
    const int c = static_cast<int>(count);
    MPI_Sendrecv(m_host[kSendHi], c, MPI_DOUBLE, hi, 2 * a, m_host[kRecvLo], c, MPI_DOUBLE, lo, 2 * a, comm,
                 MPI_STATUS_IGNORE);
    MPI_Sendrecv(m_host[kSendLo], c, MPI_DOUBLE, lo, 2 * a + 1, m_host[kRecvHi], c, MPI_DOUBLE, hi, 2 * a + 1, comm,
                 MPI_STATUS_IGNORE);

    // Back to the device, into the ghost layers (the next axis's faces include them)
    if (lo != MPI_PROC_NULL) {
      cuda_check(cudaMemcpyAsync(m_device[kRecvLo], m_host[kRecvLo], bytes, cudaMemcpyHostToDevice, s),
                 "cudaMemcpyAsync (halo face to device)");
      unpack_face<<<blocks_for(count), kBlock, 0, s>>>(field, m_device[kRecvLo], ghost_lo);
      cuda_check(cudaGetLastError(), "unpack_face launch");
    }
    if (hi != MPI_PROC_NULL) {
      cuda_check(cudaMemcpyAsync(m_device[kRecvHi], m_host[kRecvHi], bytes, cudaMemcpyHostToDevice, s),
                 "cudaMemcpyAsync (halo face to device)");
      unpack_face<<<blocks_for(count), kBlock, 0, s>>>(field, m_device[kRecvHi], ghost_hi);
      cuda_check(cudaGetLastError(), "unpack_face launch");
    }
  }
  cuda_check(cudaStreamSynchronize(s), "cudaStreamSynchronize (halo exchanged)");
}

}  // namespace heat
