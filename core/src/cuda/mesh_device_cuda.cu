/// mesh_device.h on a CUDA device: one grid-stride pass per domain over its cells or values,
/// the per-item code the host's build runs, folded with integer atomics (order keys for min /
/// max, or for flags, sums for counts): no order, so the host's bits.
#include "cuda/cuda_backend.h"
#include "cuda/cuda_check.h"
#include "cuda/device_backend.h"
#include "cuda/gpu_emulation.h"
#include "cuda/mesh_device.h"
#include "cuda/order_key.h"
#include "mesh/element_indices.h"

#include <cuda_runtime.h>

#include <algorithm>
#include <string>
#include <vector>

namespace tessera::cuda {
namespace {

constexpr unsigned kThreads = 256;

unsigned blocks_for(std::int64_t n) {
  return static_cast<unsigned>(std::clamp<std::int64_t>((n + kThreads - 1) / kThreads, 1, 65535));
}

__device__ inline std::int64_t first_thread() { return blockIdx.x * static_cast<std::int64_t>(blockDim.x) + threadIdx.x; }
__device__ inline std::int64_t thread_step() { return static_cast<std::int64_t>(gridDim.x) * blockDim.x; }

/// Min / max keys and flags of one range (or of the cells a box meets).
struct RangeKeys {
  unsigned long long* lo;
  unsigned long long* hi;
  unsigned int* flags;
};

__device__ inline void fold(const RangeKeys& k, std::size_t c, const ElementRange& r) {
  if (r.lo <= r.hi) {
    const unsigned long long lo = order_key(r.lo), hi = order_key(r.hi);
    if (lo < k.lo[c]) atomicMin(&k.lo[c], lo);  // a plain read first: a stale one costs a no-op atomic
    if (hi > k.hi[c]) atomicMax(&k.hi[c], hi);
  }
  if (r.flags != 0 && (k.flags[c] & r.flags) != r.flags) atomicOr(&k.flags[c], static_cast<unsigned int>(r.flags));
}

__global__ void init_keys(RangeKeys k, std::int64_t n, unsigned long long lo, unsigned long long hi) {
  for (std::int64_t c = first_thread(); c < n; c += thread_step()) {
    k.lo[c] = lo;
    k.hi[c] = hi;
    k.flags[c] = 0;
  }
}

/// The lowest faulty real cell (element_index_fault) into *first; the real cells into *real.
__global__ void find_index_fault(DomainAccess a, MeshGhosts ghosts, std::int64_t cells,
                                 std::int64_t vertices, unsigned long long* first, unsigned long long* real) {
  unsigned long long mine = 0;
  for (std::int64_t e = first_thread(); e < cells; e += thread_step()) {
    if (ghosts.is_ghost(e)) continue;
    ++mine;
    std::int64_t idx[8];
    Vec3 v[8];
    if (element_index_fault(a, e, vertices, idx, v) >= 0) atomicMin(first, static_cast<unsigned long long>(e));
  }
  if (mine) atomicAdd(real, mine);
}

/// Cell `cell`'s fault, by one thread.
__global__ void describe_fault(DomainAccess a, std::int64_t cell, std::int64_t vertices, MeshIndexFault* out) {
  std::int64_t idx[8];
  Vec3 v[8];
  const int k = element_index_fault(a, cell, vertices, idx, v);
  out->corner = k;
  if (k < 0) return;
  out->index = idx[k];
  if (idx[k] >= 0 && idx[k] < vertices) out->vertex = v[k];
}

/// Totals over `count` values: [0] NaN count; keys all (lo, hi, flags) and real (lo, hi).
__global__ void value_stats(DomainAccess a, MeshGhosts ghosts, bool cell_data,
                            std::int64_t count, unsigned long long* nan, RangeKeys all, RangeKeys real) {
  unsigned long long nans = 0;
  ElementRange mine_all, mine_real;
  for (std::int64_t e = first_thread(); e < count; e += thread_step()) {
    const double v = a.value(e);
    nans += v != v ? 1 : 0;
    add_value(mine_all, v);
    if (!(cell_data && ghosts.is_ghost(e)) && value_flag(v) == 0) add_value(mine_real, v);
  }
  if (nans) atomicAdd(nan, nans);
  fold(all, 0, mine_all);
  fold(real, 0, mine_real);
}

/// Every real cell's range folded into the macrocells its box meets.
__global__ void summarise_cells(DomainAccess a, MeshGhosts ghosts, std::int64_t cells,
                                MacroGrid g, RangeKeys k) {
  for (std::int64_t e = first_thread(); e < cells; e += thread_step()) {
    if (ghosts.is_ghost(e)) continue;
    double box[6];
    element_box(a, e, box);
    const ElementRange r = element_range(&a, MeshElementRef{e, 0});
    std::int64_t c0[3], c1[3];
    g.span(box, c0, c1);
    for (std::int64_t z = c0[2]; z <= c1[2]; ++z)
      for (std::int64_t y = c0[1]; y <= c1[1]; ++y)
        for (std::int64_t x = c0[0]; x <= c1[0]; ++x)
          fold(k, static_cast<std::size_t>((z * g.cells[1] + y) * g.cells[0] + x), r);
  }
}

/// The device holding the mesh's arrays (its first array's), made current, after the
/// simulation's queued work.
class MeshDevice {
 public:
  MeshDevice(const Mesh& mesh, void* stream, const std::string& what) : m_device(device_of(mesh)), m_guard(m_device) {
    if (stream)
      cuda_check(cudaStreamSynchronize(static_cast<cudaStream_t>(stream)),
                 "cudaStreamSynchronize(the simulation's stream, before " + what + ")");
    else cuda_check(cudaDeviceSynchronize(), "cudaDeviceSynchronize (before " + what + ")");
    m_backend = cuda_backend(m_device);
  }
  DeviceBackend& backend() { return *m_backend; }

 private:
  static int device_of(const Mesh& mesh) {
    for (const MeshDomain& d : mesh.domains)
      for (int s = 0; s < kMeshArraySlots; ++s) {
        const void* p = mesh_array(d, static_cast<MeshArraySlot>(s)).data;
        if (!p) continue;
        cudaPointerAttributes attr{};
        cuda_check(cudaPointerGetAttributes(&attr, p), "cudaPointerGetAttributes(mesh array)");
        return attr.device >= 0 ? attr.device : 0;
      }
    return 0;
  }
  int m_device = 0;
  DeviceGuard m_guard;
  std::shared_ptr<DeviceBackend> m_backend;
};

/// Device keys for n ranges: lo, hi (init +Inf / -Inf keys), flags, then `extra` counters (0).
struct KeyBuffer {
  BackendBuffer buf;
  RangeKeys keys{};
  unsigned long long* extra = nullptr;
  KeyBuffer(DeviceBackend& b, std::size_t n, std::size_t nextra, const std::string& what) : buf(b) {
    buf.allocate(n * (2 * sizeof(unsigned long long) + sizeof(unsigned int)) + nextra * sizeof(unsigned long long),
                 what);
    keys.lo = buf.as<unsigned long long>();
    keys.hi = keys.lo + n;
    extra = keys.hi + n;
    keys.flags = reinterpret_cast<unsigned int*>(extra + nextra);
    if (nextra) b.zero(extra, nextra * sizeof(unsigned long long), what);
    init_keys<<<blocks_for(static_cast<std::int64_t>(n)), kThreads>>>(keys, static_cast<std::int64_t>(n),
                                                                       order_key(INFINITY), order_key(-INFINITY));
    cuda_check(cudaGetLastError(), "launch of init_keys (" + what + ")");
  }
  /// Range i back on the host.
  ElementRange range(std::size_t i) const {
    unsigned long long lo = 0, hi = 0;
    unsigned int flags = 0;
    cuda_check(cudaMemcpy(&lo, keys.lo + i, sizeof lo, cudaMemcpyDeviceToHost), "cudaMemcpy(mesh range to the host)");
    cuda_check(cudaMemcpy(&hi, keys.hi + i, sizeof hi, cudaMemcpyDeviceToHost), "cudaMemcpy(mesh range to the host)");
    cuda_check(cudaMemcpy(&flags, keys.flags + i, sizeof flags, cudaMemcpyDeviceToHost),
               "cudaMemcpy(mesh range to the host)");
    ElementRange r;
    r.lo = from_key(lo);
    r.hi = from_key(hi);
    r.flags = static_cast<std::uint8_t>(flags);
    return r;
  }
};

/// The item sums of one geometry array (geometry_hash.h), added into sums[0], sums[1].
__global__ void geometry_sums(GeometryArray g, unsigned long long* sums) {
  GeometrySums s;
  for (std::int64_t i = first_thread(); i < g.count; i += thread_step())
    add_geometry_item(s, g.tag, static_cast<std::uint64_t>(i), geometry_item(g, i));
  if (s.a != 0) atomicAdd(sums, static_cast<unsigned long long>(s.a));
  if (s.b != 0) atomicAdd(sums + 1, static_cast<unsigned long long>(s.b));
}

}  // namespace

MeshIndexFault mesh_index_fault(const Mesh& mesh, void* stream) {
  if (gpu_emulation()) return mesh_index_fault_host(mesh);
  throw_if_disabled();
  MeshDevice dev(mesh, stream, "checking the mesh");
  MeshIndexFault f;
  BackendBuffer buf(dev.backend());
  buf.allocate(2 * sizeof(unsigned long long) + sizeof(MeshIndexFault), "mesh index check");
  auto* first = buf.as<unsigned long long>();
  auto* real = first + 1;
  auto* out = reinterpret_cast<MeshIndexFault*>(first + 2);
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const MeshDomain& d = mesh.domains[i];
    const unsigned long long none = ~0ull;
    cuda_check(cudaMemcpy(first, &none, sizeof none, cudaMemcpyHostToDevice), "cudaMemcpy(mesh index check)");
    dev.backend().zero(real, sizeof(unsigned long long), "mesh index check");
    const std::int64_t cells = d.cell_count();
    const DomainAccess a = DomainAccess::of(d);
    find_index_fault<<<blocks_for(cells), kThreads>>>(a, d.ghosts, cells, d.coords.count,
                                                      first, real);
    cuda_check(cudaGetLastError(), "launch of find_index_fault (mesh domain " + std::to_string(i) + ")");
    unsigned long long host[2] = {0, 0};
    cuda_check(cudaMemcpy(host, first, sizeof host, cudaMemcpyDeviceToHost),
               "find_index_fault (mesh domain " + std::to_string(i) + ")");
    f.real_cells += host[1];
    if (f.domain >= 0 || host[0] == none) continue;
    f.domain = static_cast<std::int64_t>(i);
    f.cell = static_cast<std::int64_t>(host[0]);
    describe_fault<<<1, 1>>>(a, f.cell, d.coords.count, out);
    cuda_check(cudaGetLastError(), "launch of describe_fault (mesh domain " + std::to_string(i) + ")");
    MeshIndexFault got;
    cuda_check(cudaMemcpy(&got, out, sizeof got, cudaMemcpyDeviceToHost), "describe_fault (mesh index check)");
    f.corner = got.corner;
    f.index = got.index;
    f.vertex = got.vertex;
  }
  return f;
}

MeshValueStats mesh_value_stats(const Mesh& mesh, void* stream) {
  if (gpu_emulation()) return mesh_value_stats_host(mesh);
  throw_if_disabled();
  MeshDevice dev(mesh, stream, "the mesh's value range");
  KeyBuffer k(dev.backend(), 2, 1, "mesh value totals");
  const RangeKeys all{k.keys.lo, k.keys.hi, k.keys.flags};
  const RangeKeys real{k.keys.lo + 1, k.keys.hi + 1, k.keys.flags + 1};
  MeshValueStats s;
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const MeshDomain& d = mesh.domains[i];
    value_stats<<<blocks_for(d.field.count), kThreads>>>(DomainAccess::of(d), d.ghosts,
                                                         d.field.association == Association::Cell, d.field.count,
                                                         k.extra, all, real);
    cuda_check(cudaGetLastError(), "launch of value_stats (mesh domain " + std::to_string(i) + ")");
    s.values += static_cast<std::uint64_t>(d.field.count);
  }
  cuda_check(cudaMemcpy(&s.nan, k.extra, sizeof s.nan, cudaMemcpyDeviceToHost), "value_stats (mesh value totals)");
  s.all = k.range(0);
  s.real = k.range(1);
  return s;
}

FieldSummary::Parts mesh_summary_cells(const Mesh& mesh, const MacroGrid& g, void* stream) {
  if (gpu_emulation()) return mesh_summary_cells_host(mesh, g);
  throw_if_disabled();
  MeshDevice dev(mesh, stream, "summarising the mesh");
  const auto n = static_cast<std::size_t>(g.cells[0] * g.cells[1] * g.cells[2]);
  KeyBuffer k(dev.backend(), n, 0, "mesh macrocells");
  for (std::size_t i = 0; i < mesh.domains.size(); ++i) {
    const MeshDomain& d = mesh.domains[i];
    const std::int64_t cells = d.cell_count();
    summarise_cells<<<blocks_for(cells), kThreads>>>(DomainAccess::of(d), d.ghosts, cells, g,
                                                     k.keys);
    cuda_check(cudaGetLastError(), "launch of summarise_cells (mesh domain " + std::to_string(i) + ")");
  }
  cuda_check(cudaDeviceSynchronize(), "summarise_cells (mesh macrocells)");
  std::vector<unsigned long long> lo(n), hi(n);
  std::vector<unsigned int> flags(n);
  cuda_check(cudaMemcpy(lo.data(), k.keys.lo, n * sizeof(unsigned long long), cudaMemcpyDeviceToHost),
             "cudaMemcpy(mesh macrocells to the host)");
  cuda_check(cudaMemcpy(hi.data(), k.keys.hi, n * sizeof(unsigned long long), cudaMemcpyDeviceToHost),
             "cudaMemcpy(mesh macrocells to the host)");
  cuda_check(cudaMemcpy(flags.data(), k.keys.flags, n * sizeof(unsigned int), cudaMemcpyDeviceToHost),
             "cudaMemcpy(mesh macrocells to the host)");
  FieldSummary::Parts parts;
  for (int a = 0; a < 3; ++a) parts.cells[a] = g.cells[a];
  parts.lo.resize(n);
  parts.hi.resize(n);
  parts.flags.resize(n);
  for (std::size_t c = 0; c < n; ++c) {
    parts.lo[c] = from_key(lo[c]);
    parts.hi[c] = from_key(hi[c]);
    parts.flags[c] = static_cast<std::uint8_t>(flags[c]);
  }
  return parts;
}

GeometrySums mesh_geometry_sums(const Mesh& mesh, void* stream) {
  if (gpu_emulation()) return mesh_geometry_sums_host(mesh);
  throw_if_disabled();
  MeshDevice dev(mesh, stream, "hashing the mesh's geometry");
  BackendBuffer buf(dev.backend());
  buf.allocate(2 * sizeof(unsigned long long), "mesh geometry hash");
  auto* sums = buf.as<unsigned long long>();
  dev.backend().zero(sums, 2 * sizeof(unsigned long long), "mesh geometry hash");
  for (const GeometryArray& g : geometry_arrays(mesh)) {
    if (g.count == 0) continue;
    geometry_sums<<<blocks_for(g.count), kThreads>>>(g, sums);
    cuda_check(cudaGetLastError(), "launch of geometry_sums (mesh geometry hash)");
  }
  unsigned long long host[2] = {0, 0};
  cuda_check(cudaMemcpy(host, sums, sizeof host, cudaMemcpyDeviceToHost), "geometry_sums (mesh geometry hash)");
  return GeometrySums{host[0], host[1]};
}

}  // namespace tessera::cuda
