#pragma once
/// CudaHaloExchange: HaloExchange (halo_exchange.h) for an array in device memory, without
/// CUDA-aware MPI: only the faces move. For each axis in turn, the two owned layers next to
/// the neighbours are packed on the device into contiguous buffers, copied to pinned host
/// buffers, sent and received with MPI_Sendrecv (the tags and order of HaloExchange), copied
/// back and unpacked into the ghost layers. As in HaloExchange, each face spans the full
/// ghosted extent of the other two axes and the axes go one after the other, so edge and
/// corner ghosts end up filled too; at the domain boundary (MPI_PROC_NULL) nothing moves, and
/// a rank without neighbours makes no copy at all.
#include "cart_decomposition.h"

#include <cstddef>
#include <cstdint>

struct CUstream_st;  // cudaStream_t

namespace heat {

class CudaHaloExchange {
 public:
  /// Allocates the face buffers (device and pinned host memory, for the largest face) on the
  /// current device; throws std::runtime_error naming the CUDA call that failed. The kernels
  /// and copies run on `stream`.
  CudaHaloExchange(const CartDecomposition& decomp, CUstream_st* stream);
  ~CudaHaloExchange();
  CudaHaloExchange(const CudaHaloExchange&) = delete;
  CudaHaloExchange& operator=(const CudaHaloExchange&) = delete;

  /// Collective over decomp.comm(): fills the six ghost faces of the device array `field`
  /// ((owned[0]+2) x (owned[1]+2) x (owned[2]+2) doubles, i fastest). Returns when the stream
  /// has finished.
  void exchange(double* field);

  /// Bytes this rank sends per exchange (for reports); as many cross PCIe each way.
  std::uint64_t bytes_per_exchange() const { return m_bytes; }

 private:
  void release() noexcept;

  const CartDecomposition& m_decomp;
  CUstream_st* m_stream;
  Index3 m_dims{};  ///< the array's extent, ghosts included
  std::uint64_t m_bytes = 0;
  /// [0] send low, [1] send high, [2] receive low, [3] receive high: each the largest face
  double* m_device[4] = {};
  double* m_host[4] = {};
};

}  // namespace heat
