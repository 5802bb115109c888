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
#include "cuda/gpu_emulation.h"
#include "cuda/order_key.h"

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
  std::int64_t nc[3];
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
    // The cells holding the vertex per axis: its own, and the previous one on an inner boundary
    std::int64_t own[3], prev[3];
    for (int ax = 0; ax < 3; ++ax) {
      own[ax] = min(g[ax] / a.edge, a.nc[ax] - 1);
      prev[ax] = g[ax] % a.edge == 0 && g[ax] > 0 && g[ax] / a.edge <= a.nc[ax] - 1 ? g[ax] / a.edge - 1 : own[ax];
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

std::shared_ptr<const FieldSummary> cuda_field_summary(const FieldView& field, int edge, void* stream) {
  using cuda::cuda_check;
  if (cuda::gpu_emulation()) return FieldSummary::build(field, edge);  // its device memory is host memory
  cuda::throw_if_disabled();
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  field.validate("field");
  if (cuda_memory_kind(field.data) == MemoryKind::Host) return FieldSummary::build(field, edge);

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
  FieldSummary::Parts parts;
  for (int ax = 0; ax < 3; ++ax) {
    a.s[ax] = field.byte_strides[ax];
    a.n[ax] = field.dims[ax];
    a.nc[ax] = std::max<std::int64_t>(1, (field.dims[ax] - 1 + edge - 1) / edge);  // summary_accumulate.h cells_along
    parts.cells[ax] = a.nc[ax];
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

  // The parts on the host: keys back to doubles, the finite min / max over the cells
  std::vector<unsigned long long> lo(ncells), hi(ncells);
  std::vector<unsigned int> flags(ncells);
  cuda_check(cudaMemcpy(lo.data(), a.lo, ncells * sizeof(unsigned long long), cudaMemcpyDeviceToHost),
             "cudaMemcpy(field summary to the host)");
  cuda_check(cudaMemcpy(hi.data(), a.hi, ncells * sizeof(unsigned long long), cudaMemcpyDeviceToHost),
             "cudaMemcpy(field summary to the host)");
  cuda_check(cudaMemcpy(flags.data(), a.flags, ncells * sizeof(unsigned int), cudaMemcpyDeviceToHost),
             "cudaMemcpy(field summary to the host)");
  cuda_check(cudaMemcpy(&parts.nan, a.nan, sizeof(unsigned long long), cudaMemcpyDeviceToHost),
             "cudaMemcpy(field summary to the host)");
  parts.lo.resize(ncells);
  parts.hi.resize(ncells);
  parts.flags.resize(ncells);
  for (std::size_t c = 0; c < ncells; ++c) {
    parts.lo[c] = cuda::from_key(lo[c]);
    parts.hi[c] = cuda::from_key(hi[c]);
    parts.flags[c] = static_cast<std::uint8_t>(flags[c]);
    parts.vmin = parts.lo[c] < parts.vmin ? parts.lo[c] : parts.vmin;
    parts.vmax = parts.vmax < parts.hi[c] ? parts.hi[c] : parts.vmax;
  }
  return FieldSummary::from_parts(std::move(parts), FieldLayout::of(field), edge);
}

}  // namespace tessera
