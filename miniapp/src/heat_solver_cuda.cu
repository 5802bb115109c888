#include "cuda_check.h"
#include "heat_solver_cuda.h"

#include <mpi.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace heat {
namespace {

/// One step's kernel arguments, by value: the arrays, the block's place in the grid, the
/// stencil's coefficients and the sources' stamps (computed on the host by source_stamp).
struct StepArgs {
  const double* T;
  double* next;
  std::int64_t sy, sz;  ///< array strides of j and k (i is 1)
  std::int64_t n[3], off[3], g[3];
  double h[3];
  double cx, cy, cz, dt, boundary;
  int nsources;
  SourceStamp src[CudaHeatSolver::kMaxSources];
};
static_assert(std::is_trivially_copyable_v<StepArgs>);

/// HeatSolver::step and add_sources for one vertex, in the same order of operations: the
/// diffusion update, then each source's term added in turn (walls keep boundary).
/// Threads: x along i, blocks of the grid's y and z walk j and k.
__global__ void step_kernel(StepArgs a) {
  const std::int64_t i = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x;
  if (i >= a.n[0]) return;
  const std::int64_t gi = a.off[0] + i;
  for (std::int64_t k = blockIdx.z; k < a.n[2]; k += gridDim.z) {
    const std::int64_t gk = a.off[2] + k;
    for (std::int64_t j = blockIdx.y; j < a.n[1]; j += gridDim.y) {
      const std::int64_t gj = a.off[1] + j;
      const std::int64_t c = (k + 1) * a.sz + (j + 1) * a.sy + (i + 1);
      if (gk == 0 || gk == a.g[2] - 1 || gj == 0 || gj == a.g[1] - 1 || gi == 0 || gi == a.g[0] - 1) {
        a.next[c] = a.boundary;
        continue;
      }
      // Diffusion: the six neighbours (ghosts hold the neighbouring ranks' values)
      const double T = a.T[c];
      const double lap = a.cx * (a.T[c - 1] - 2.0 * T + a.T[c + 1]) + a.cy * (a.T[c - a.sy] - 2.0 * T + a.T[c + a.sy]) +
                         a.cz * (a.T[c - a.sz] - 2.0 * T + a.T[c + a.sz]);
      double v = T + a.dt * lap;
      // Sources, one after the other, where their stamp covers the vertex
      for (int s = 0; s < a.nsources; ++s) {
        const SourceStamp& st = a.src[s];
        if (i < st.lo[0] || i > st.hi[0] || j < st.lo[1] || j > st.hi[1] || k < st.lo[2] || k > st.hi[2]) continue;
        const double dx = static_cast<double>(a.off[0] + i) * a.h[0] - st.centre[0];
        const double dy = static_cast<double>(a.off[1] + j) * a.h[1] - st.centre[1];
        const double dz = static_cast<double>(a.off[2] + k) * a.h[2] - st.centre[2];
        v += st.amp * exp(-(dx * dx + dy * dy + dz * dz) * st.inv_2s2);
      }
      a.next[c] = v;
    }
  }
}

/// The initial state, as HeatSolver's constructor makes it: initial_value everywhere (ghosts
/// included), boundary_value on the owned wall vertices.
__global__ void fill_kernel(double* f, std::int64_t total, std::int64_t d0, std::int64_t d1, Index3 n, Index3 off,
                            Index3 g, double initial, double boundary) {
  for (std::int64_t e = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; e < total;
       e += static_cast<std::int64_t>(gridDim.x) * blockDim.x) {
    // Array position (ghost layer at 0), then owned local index
    const std::int64_t i = e % d0 - 1, j = (e / d0) % d1 - 1, k = e / (d0 * d1) - 1;
    const bool owned = i >= 0 && i < n[0] && j >= 0 && j < n[1] && k >= 0 && k < n[2];
    const std::int64_t gi = off[0] + i, gj = off[1] + j, gk = off[2] + k;
    const bool wall = gi == 0 || gj == 0 || gk == 0 || gi == g[0] - 1 || gj == g[1] - 1 || gk == g[2] - 1;
    f[e] = owned && wall ? boundary : initial;
  }
}

constexpr int kRangeThreads = 256;
constexpr int kRangeBlocks = 256;

/// Per-block min and max over the owned vertices: out[2 b] and out[2 b + 1].
__global__ void range_kernel(const double* __restrict__ T, Index3 n, std::int64_t sy, std::int64_t sz,
                             double* __restrict__ out) {
  __shared__ double lo_s[kRangeThreads], hi_s[kRangeThreads];
  double lo = INFINITY, hi = -INFINITY;
  const std::int64_t count = n[0] * n[1] * n[2];
  for (std::int64_t e = blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; e < count;
       e += static_cast<std::int64_t>(gridDim.x) * blockDim.x) {
    const std::int64_t i = e % n[0], j = (e / n[0]) % n[1], k = e / (n[0] * n[1]);
    const double v = T[(k + 1) * sz + (j + 1) * sy + (i + 1)];
    lo = fmin(lo, v);
    hi = fmax(hi, v);
  }
  lo_s[threadIdx.x] = lo;
  hi_s[threadIdx.x] = hi;
  __syncthreads();
  for (int w = kRangeThreads / 2; w > 0; w /= 2) {
    if (static_cast<int>(threadIdx.x) < w) {
      lo_s[threadIdx.x] = fmin(lo_s[threadIdx.x], lo_s[threadIdx.x + w]);
      hi_s[threadIdx.x] = fmax(hi_s[threadIdx.x], hi_s[threadIdx.x + w]);
    }
    __syncthreads();
  }
  if (threadIdx.x == 0) {
    out[2 * blockIdx.x] = lo_s[0];
    out[2 * blockIdx.x + 1] = hi_s[0];
  }
}

unsigned clamp_dim(std::int64_t v, std::int64_t most) {
  return static_cast<unsigned>(std::clamp<std::int64_t>(v, 1, most));
}

}  // namespace

CudaHeatSolver::CudaHeatSolver(const CartDecomposition& decomp, const HeatParams& params)
    : m_decomp(decomp), m_params(params) {
  // The checks of HeatSolver: the same arguments on every rank, so every rank throws alike
  m_h = checked_spacing(decomp, params);
  if (params.sources.size() > static_cast<std::size_t>(kMaxSources))
    throw std::invalid_argument("the CUDA heat solver takes at most " + std::to_string(kMaxSources) +
                                " heat sources, got " + std::to_string(params.sources.size()));
  for (int a = 0; a < 3; ++a) m_dims[a] = decomp.owned()[a] + 2;
  m_stable_dt = stable_time_step(m_h, params);

  // Device arrays and the initial state; the ranks agree before the collective halo exchange
  std::string fault;
  try {
    cuda_check(cudaGetDevice(&m_device), "cudaGetDevice");
    cudaStream_t s = nullptr;
    cuda_check(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking), "cudaStreamCreateWithFlags");
    m_stream = s;
    const std::int64_t total = m_dims[0] * m_dims[1] * m_dims[2];
    const std::size_t bytes = static_cast<std::size_t>(total) * sizeof(double);
    cuda_check(cudaMalloc(&m_T, bytes), "cudaMalloc (temperature)");
    cuda_check(cudaMalloc(&m_next, bytes), "cudaMalloc (temperature, next step)");
    cuda_check(cudaMalloc(&m_range, 2 * kRangeBlocks * sizeof(double)), "cudaMalloc (range)");
    m_halo = std::make_unique<CudaHaloExchange>(decomp, m_stream);
    const unsigned blocks = clamp_dim((total + 255) / 256, 1 << 16);
    for (double* f : {m_T, m_next})
      fill_kernel<<<blocks, 256, 0, s>>>(f, total, m_dims[0], m_dims[1], decomp.owned(), decomp.offset(),
                                         decomp.global_dims(), params.initial_value, params.boundary_value);
    cuda_check(cudaGetLastError(), "fill_kernel launch");
    cuda_check(cudaStreamSynchronize(s), "cudaStreamSynchronize (initial state)");
  } catch (const std::exception& e) {
    fault = e.what();
  }
  int ok = fault.empty() ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, decomp.comm());
  if (!ok) {
    release();
    throw std::runtime_error(fault.empty() ? "the CUDA heat solver's setup failed on another rank" : fault);
  }
  try {
    m_halo->exchange(m_T);
  } catch (...) {
    release();
    throw;
  }
}

CudaHeatSolver::~CudaHeatSolver() { release(); }

void CudaHeatSolver::release() noexcept {
  m_halo.reset();
  for (double** p : {&m_T, &m_next, &m_range}) {
    if (*p) cudaFree(*p);
    *p = nullptr;
  }
  if (m_stream) cudaStreamDestroy(m_stream);
  m_stream = nullptr;
}

void CudaHeatSolver::step(double dt) {
  check_time_step(dt, m_stable_dt, m_params.safety);
  StepArgs a{};
  a.T = m_T;
  a.next = m_next;
  a.sy = m_dims[0];
  a.sz = m_dims[0] * m_dims[1];
  for (int d = 0; d < 3; ++d) {
    a.n[d] = m_decomp.owned()[d];
    a.off[d] = m_decomp.offset()[d];
    a.g[d] = m_decomp.global_dims()[d];
    a.h[d] = m_h[d];
  }
  a.cx = m_params.alpha / (m_h[0] * m_h[0]);
  a.cy = m_params.alpha / (m_h[1] * m_h[1]);
  a.cz = m_params.alpha / (m_h[2] * m_h[2]);
  a.dt = dt;
  a.boundary = m_params.boundary_value;
  a.nsources = static_cast<int>(m_params.sources.size());
  for (int s = 0; s < a.nsources; ++s)
    a.src[s] = source_stamp(m_params.sources[static_cast<std::size_t>(s)], m_time, dt, m_decomp, m_h);

  constexpr int kThreads = 128;
  const dim3 grid(clamp_dim((a.n[0] + kThreads - 1) / kThreads, std::numeric_limits<int>::max()),
                  clamp_dim(a.n[1], 65535), clamp_dim(a.n[2], 65535));
  step_kernel<<<grid, kThreads, 0, m_stream>>>(a);
  cuda_check(cudaGetLastError(), "step_kernel launch");
  std::swap(m_T, m_next);
  m_time += dt;
  ++m_steps;
  m_halo->exchange(m_T);  // (returns with the stream idle)
}

std::pair<double, double> CudaHeatSolver::local_range() const {
  const Index3& n = m_decomp.owned();
  const std::int64_t count = n[0] * n[1] * n[2];
  const unsigned blocks = clamp_dim((count + kRangeThreads - 1) / kRangeThreads, kRangeBlocks);
  range_kernel<<<blocks, kRangeThreads, 0, m_stream>>>(m_T, n, m_dims[0], m_dims[0] * m_dims[1], m_range);
  cuda_check(cudaGetLastError(), "range_kernel launch");
  std::vector<double> partial(2 * static_cast<std::size_t>(blocks));
  cuda_check(
      cudaMemcpyAsync(partial.data(), m_range, partial.size() * sizeof(double), cudaMemcpyDeviceToHost, m_stream),
      "cudaMemcpyAsync (range)");
  cuda_check(cudaStreamSynchronize(m_stream), "cudaStreamSynchronize (range)");
  double lo = partial[0], hi = partial[1];
  for (unsigned b = 1; b < blocks; ++b) {
    lo = std::min(lo, partial[2 * b]);
    hi = std::max(hi, partial[2 * b + 1]);
  }
  return {lo, hi};
}

std::vector<double> CudaHeatSolver::array_values() const {
  std::vector<double> v(static_cast<std::size_t>(m_dims[0] * m_dims[1] * m_dims[2]));
  cuda_check(cudaMemcpyAsync(v.data(), m_T, v.size() * sizeof(double), cudaMemcpyDeviceToHost, m_stream),
             "cudaMemcpyAsync (temperature to host)");
  cuda_check(cudaStreamSynchronize(m_stream), "cudaStreamSynchronize (temperature to host)");
  return v;
}

std::vector<double> CudaHeatSolver::owned_values() const {
  const std::vector<double> all = array_values();
  const Index3& n = m_decomp.owned();
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(n[0] * n[1] * n[2]));
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i)
        v.push_back(all[static_cast<std::size_t>(((k + 1) * m_dims[1] + (j + 1)) * m_dims[0] + (i + 1))]);
  return v;
}

}  // namespace heat
