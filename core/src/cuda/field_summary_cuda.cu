/// cuda_field_summary (cuda_render.h): the FieldSummary of a device or managed field by a
/// reduction on the device that holds it. Each thread reads one vertex (the dtype's exact
/// double, zeros as +0.0: summary_accumulate.h's rules) and folds it into every macrocell that
/// touches it (its own and, on an inner cell boundary, the previous cell's +1 overlap) with
/// atomic min / max on order-preserving integer keys, an atomic or of the NaN / +Inf / -Inf
/// flags and an atomic NaN count. Min, max, or and integer sums do not depend on the order,
/// so the result is FieldSummary::build's bit for bit.
#include <tessera/cuda_render.h>
#include <tessera/field_summary.h>

#include "cuda/cuda_backend.h"
#include "cuda/cuda_check.h"
#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"
#include "cuda/order_key.h"
#include "field/summary_accumulate.h"

#include <cuda_runtime.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::cuda {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct SummaryArgs {
  const unsigned char* base;
  std::int64_t s[3];
  std::int64_t n[3];
  std::int64_t off[3];  ///< global vertex of the block's (0, 0, 0)
  std::int64_t gc[3];   ///< macrocells of the global field per axis
  std::int64_t c0[3];   ///< the first global macrocell of the window below
  std::int64_t nc[3];   ///< the window of macrocells the block touches (lo, hi, flags are over it)
  std::int64_t edge;
  DType dtype;
  unsigned long long* lo;  ///< per cell, keys
  unsigned long long* hi;
  unsigned int* flags;      ///< per cell: bit 0 NaN, 1 +Inf, 2 -Inf
  unsigned long long* nan;  ///< one count
};

__global__ void init_cells(SummaryArgs a, std::int64_t cells, unsigned long long lo_key, unsigned long long hi_key) {
  for (std::int64_t c = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; c < cells;
       c += static_cast<std::int64_t>(gridDim.x) * blockDim.x) {
    a.lo[c] = lo_key;
    a.hi[c] = hi_key;
    a.flags[c] = 0;
  }
}

__global__ void summarise_vertices(SummaryArgs a) {
  const std::int64_t count = a.n[0] * a.n[1] * a.n[2];
  for (std::int64_t v = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; v < count;
       v += static_cast<std::int64_t>(gridDim.x) * blockDim.x) {
    const std::int64_t g[3] = {v % a.n[0], (v / a.n[0]) % a.n[1], v / (a.n[0] * a.n[1])};
    double x = detail::load_as_double(a.dtype, a.base + g[0] * a.s[0] + g[1] * a.s[1] + g[2] * a.s[2]);
    x = x == 0.0 ? 0.0 : x;  // zeros as +0.0 (summary_accumulate.h, canonical)
    // The global cells holding the vertex per axis: its own, and the previous one on an inner
    // boundary (summary_accumulate.h's rule), then as indices into the window
    std::int64_t own[3], prev[3];
    for (int ax = 0; ax < 3; ++ax) {
      const std::int64_t G = g[ax] + a.off[ax];
      own[ax] = min(G / a.edge, a.gc[ax] - 1);
      prev[ax] = G % a.edge == 0 && G > 0 && G / a.edge <= a.gc[ax] - 1 ? G / a.edge - 1 : own[ax];
      own[ax] -= a.c0[ax];
      prev[ax] -= a.c0[ax];
    }
    const bool finite = x - x == 0.0;
    const unsigned int flag = finite ? 0u : (x != x ? 1u : (x > 0.0 ? 2u : 4u));
    if (flag == 1u) atomicAdd(a.nan, 1ull);
    const unsigned long long key = finite ? order_key(x) : 0ull;
    for (int q = 0; q < 8; ++q) {
      const std::int64_t ci = q & 1 ? prev[0] : own[0], cj = q & 2 ? prev[1] : own[1], ck = q & 4 ? prev[2] : own[2];
      // each distinct cell once
      if ((q & 1 && prev[0] == own[0]) || (q & 2 && prev[1] == own[1]) || (q & 4 && prev[2] == own[2])) continue;
      const std::int64_t c = (ck * a.nc[1] + cj) * a.nc[0] + ci;
      if (finite) {
        // a plain read first: a stale value only costs an atomic that changes nothing
        if (key < a.lo[c]) atomicMin(&a.lo[c], key);
        if (key > a.hi[c]) atomicMax(&a.hi[c], key);
      } else if ((a.flags[c] & flag) == 0) {
        atomicOr(&a.flags[c], flag);
      }
    }
  }
}

}  // namespace

}  // namespace tessera::cuda

namespace tessera {

namespace {

/// The summary of the device block `field` at `offset` in a field of `global` vertices, folded
/// into `parts` (the global field's cells): a reduction on the device over the window of
/// macrocells the block touches, merged on the host.
void summarise_on_device(FieldSummary::Parts& parts, const FieldView& field, const std::int64_t offset[3],
                         const std::int64_t global[3], int edge, void* stream) {
  using cuda::cuda_check;
  // The device that holds the field, after the simulation's queued work
  cudaPointerAttributes attr{};
  cuda_check(cudaPointerGetAttributes(&attr, field.data), "cudaPointerGetAttributes(field)");
  const int device = attr.device >= 0 ? attr.device : 0;
  const cuda::DeviceGuard guard(device);
  if (stream)
    cuda_check(cudaStreamSynchronize(static_cast<cudaStream_t>(stream)),
               "cudaStreamSynchronize(the simulation's stream, before summarising the field)");
  else cuda_check(cudaDeviceSynchronize(), "cudaDeviceSynchronize (before summarising the field)");

  cuda::SummaryArgs a{};
  a.base = static_cast<const unsigned char*>(field.data);
  a.edge = edge;
  a.dtype = field.dtype;
  for (int ax = 0; ax < 3; ++ax) {
    a.s[ax] = field.byte_strides[ax];
    a.n[ax] = field.dims[ax];
    a.off[ax] = offset[ax];
    a.gc[ax] = parts.cells[ax];
    std::int64_t last = 0;
    summary_detail::cell_window(offset[ax], field.dims[ax], global[ax], edge, a.c0[ax], last);
    a.nc[ax] = last - a.c0[ax] + 1;
  }
  const std::int64_t cells = a.nc[0] * a.nc[1] * a.nc[2];
  const auto ncells = static_cast<std::size_t>(cells);
  cuda::BackendBuffer buf(*cuda::cuda_backend(device));
  buf.allocate(ncells * (2 * sizeof(unsigned long long) + sizeof(unsigned int)) + sizeof(unsigned long long),
               "field summary cells");
  auto* p = buf.as<unsigned char>();
  a.lo = reinterpret_cast<unsigned long long*>(p);
  a.hi = a.lo + ncells;
  a.nan = a.hi + ncells;
  a.flags = reinterpret_cast<unsigned int*>(a.nan + 1);
  cuda_check(cudaMemset(a.nan, 0, sizeof(unsigned long long)), "cudaMemset(field summary NaN count)");

  constexpr unsigned kThreads = 256;
  const auto blocks_for = [](std::int64_t n) {
    return static_cast<unsigned>(std::clamp<std::int64_t>((n + kThreads - 1) / kThreads, 1, 65535));
  };
  cuda::init_cells<<<blocks_for(cells), kThreads>>>(a, cells, cuda::order_key(cuda::kInf),
                                                    cuda::order_key(-cuda::kInf));
  cuda_check(cudaGetLastError(), "launch of init_cells (field summary)");
  cuda::summarise_vertices<<<blocks_for(field.vertex_count()), kThreads>>>(a);
  cuda_check(cudaGetLastError(), "launch of summarise_vertices (field summary)");
  cuda_check(cudaDeviceSynchronize(),
             "summarise_vertices (field summary of " + std::to_string(field.vertex_count()) + " vertices)");

  // The window on the host: keys back to doubles, merged into the global cells
  std::vector<unsigned long long> lo(ncells), hi(ncells);
  std::vector<unsigned int> flags(ncells);
  std::uint64_t nan = 0;
  cuda_check(cudaMemcpy(lo.data(), a.lo, ncells * sizeof(unsigned long long), cudaMemcpyDeviceToHost),
             "cudaMemcpy(field summary to the host)");
  cuda_check(cudaMemcpy(hi.data(), a.hi, ncells * sizeof(unsigned long long), cudaMemcpyDeviceToHost),
             "cudaMemcpy(field summary to the host)");
  cuda_check(cudaMemcpy(flags.data(), a.flags, ncells * sizeof(unsigned int), cudaMemcpyDeviceToHost),
             "cudaMemcpy(field summary to the host)");
  cuda_check(cudaMemcpy(&nan, a.nan, sizeof(unsigned long long), cudaMemcpyDeviceToHost),
             "cudaMemcpy(field summary to the host)");
  parts.nan += nan;
  std::size_t w = 0;
  for (std::int64_t k = 0; k < a.nc[2]; ++k)
    for (std::int64_t j = 0; j < a.nc[1]; ++j)
      for (std::int64_t i = 0; i < a.nc[0]; ++i, ++w) {
        const auto c = static_cast<std::size_t>(((k + a.c0[2]) * parts.cells[1] + j + a.c0[1]) * parts.cells[0] +
                                                i + a.c0[0]);
        const double l = cuda::from_key(lo[w]), h = cuda::from_key(hi[w]);
        parts.lo[c] = l < parts.lo[c] ? l : parts.lo[c];
        parts.hi[c] = parts.hi[c] < h ? h : parts.hi[c];
        parts.flags[c] |= static_cast<std::uint8_t>(flags[w]);
        parts.vmin = l < parts.vmin ? l : parts.vmin;
        parts.vmax = parts.vmax < h ? h : parts.vmax;
      }
}

}  // namespace

std::shared_ptr<const FieldSummary> cuda_field_summary(const FieldView& field, int edge, void* stream) {
  if (const auto e = cuda::gpu_emulation()) {  // its device memory is host memory
    cuda::emulated_copy_out(*e, field.data, "cuda_field_summary");
    return FieldSummary::build(field, edge);
  }
  cuda::throw_if_disabled();
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  field.validate("field");
  if (cuda_memory_kind(field.data) == MemoryKind::Host) return FieldSummary::build(field, edge);
  const std::int64_t origin[3] = {0, 0, 0};
  FieldSummary::Parts parts = FieldSummary::partial(FieldView{}, origin, field.dims, edge);  // empty parts
  summarise_on_device(parts, field, origin, field.dims, edge, stream);
  return FieldSummary::from_parts(std::move(parts), FieldLayout::of(field), edge);
}

void cuda_field_summary_accumulate(FieldSummary::Parts& parts, const FieldView& block, const std::int64_t offset[3],
                                   const std::int64_t global_dims[3], int edge, void* stream) {
  if (const auto e = cuda::gpu_emulation(); e || block.data == nullptr) {  // an emulated GPU's: host memory
    if (e) cuda::emulated_copy_out(*e, block.data, "cuda_field_summary_accumulate");
    return FieldSummary::accumulate(parts, block, offset, global_dims, edge);
  }
  cuda::throw_if_disabled();
  summary_detail::check_parts(parts, global_dims, edge);
  block.validate("block");
  summary_detail::check_block_inside(block.dims, offset, global_dims);
  if (cuda_memory_kind(block.data) == MemoryKind::Host)
    return FieldSummary::accumulate(parts, block, offset, global_dims, edge);
  summarise_on_device(parts, block, offset, global_dims, edge, stream);
}

}  // namespace tessera
