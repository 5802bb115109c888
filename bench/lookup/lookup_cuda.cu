// lookup_cuda: the GPU's ceiling for the operation the renderer repeats most, a trilinear
// lookup of a scalar volume, with nothing of a path around it (the GPU's bench/lookup/
// lookup_limit; issue 42). It is the ceiling beside which the CUDA renderer's achieved lookups
// per second (bench/perf/ete.py --device cuda, "M lookups/s") are read.
//
//   lookup_cuda [--sizes 128,256] [--threads-total N] [--per-thread K] [--rays-side S]
//               [--reps R] [--device D] [--raw FILE NX NY NZ int16|uint8|float32] [--csv FILE]
//
// Fields: lookup_limit's synthetic CT-like volume (values 0 to 2000) at each --sizes edge, held
// as float32 and as int16 (the same values rounded), and --raw's volume when given. Patterns:
//   random  every thread K lookups at uniformly random points of the box (incoherent: the
//           worst case, a lookup's 8 corners in other cache lines than its neighbours')
//   march   one thread per pixel of an S x S pinhole camera (lookup_limit's rays), fixed steps
//           of half a voxel through the whole box (coherent: neighbouring threads read
//           neighbouring cells)
//   delta   the same rays, lookup_limit's delta-tracking loop: exponential steps against a
//           constant majorant, the opacity table after each lookup, a ray ends at a real
//           collision (divergent ray lengths, as the renderer's free flights)
// Arithmetic:
//   kernel  double, the renderer's own blend (core/src/kernel/trilinear.h, TESSERA_HOST_DEVICE:
//           the same source the CPU and the CUDA renderer compile)
//   float   float throughout (what a float32 kernel could reach)
//   tex     (float32 fields only) the texture unit's hardware trilinear filter: 8-bit
//           fractional weights, too coarse for the renderer's images, a bound on the memory side
// Prints G lookups/s per (field, pattern, arithmetic), the kernels' registers and local
// memory (spills and stack, from cudaFuncGetAttributes), and checks the delta pattern's count
// and checksum against lookup_limit's scalar-float loop on the CPU (the first 65,536 rays).
// A benchmark: it prints figures and writes CSV, it asserts nothing.
#include <cuda_runtime.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "kernel/trilinear.h"
#include "lookup_kernels.h"

using lookup_bench::kTableSize;
using lookup_bench::Ray;

namespace {

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess)
    throw std::runtime_error(std::string(what) + ": " + cudaGetErrorName(e) + ": " + cudaGetErrorString(e));
}

// ---------------------------------------------------------------------------------------------
// Device side
// ---------------------------------------------------------------------------------------------

__device__ inline std::uint32_t d_ray_seed(std::uint32_t ray) {  // lookup_bench::ray_seed
  std::uint32_t h = ray * 0x9E3779B9u + 0x7F4A7C15u;
  h ^= h >> 16;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  return h | 1u;
}
__device__ inline std::uint32_t d_next_u32(std::uint32_t& s) {
  s ^= s << 13;
  s ^= s >> 17;
  s ^= s << 5;
  return s;
}
__device__ inline float d_unit_open0(std::uint32_t r) { return float((r >> 8) + 1) * (1.0f / 16777216.0f); }

enum class Arith { Kernel, Float, Tex };

/// A uniform grid of T, x fastest, read through the read-only cache.
template <class T>
struct Grid {
  const T* __restrict__ v;
  cudaTextureObject_t tex;  ///< float32 fields: the same values in a 3-D texture
  int n[3];
  long long sy, sz;
};

/// The field at voxel-space point p (clamped to the box), in arithmetic A.
template <Arith A, class T>
__device__ __forceinline__ float lookup(const Grid<T>& g, float px, float py, float pz) {
  if constexpr (A == Arith::Tex) {
    // Texel centres at integer + 0.5: voxel-space p is texture coordinate p + 0.5
    return tex3D<float>(g.tex, px + 0.5f, py + 0.5f, pz + 0.5f);
  } else {
    using R = std::conditional_t<A == Arith::Kernel, double, float>;
    const R p[3] = {R(px), R(py), R(pz)};
    int i[3];
    R f[3];
    for (int a = 0; a < 3; ++a) {
      const R hi = R(g.n[a] - 1);
      const R q = p[a] < R(0) ? R(0) : (p[a] > hi ? hi : p[a]);
      int ii = int(q);
      if (ii > g.n[a] - 2) ii = g.n[a] - 2;
      i[a] = ii;
      f[a] = q - R(ii);
    }
    const T* c = g.v + i[0] + i[1] * g.sy + i[2] * g.sz;
    const long long sy = g.sy, sz = g.sz;
    if constexpr (A == Arith::Kernel) {
      // The renderer's blend, the same source as the CPU's and the CUDA renderer's
      const double fd[3] = {f[0], f[1], f[2]};
      return float(tessera::trilinear([&](int dx, int dy, int dz) { return double(c[dx + dy * sy + dz * sz]); }, fd));
    } else {
      const float c000 = float(c[0]), c100 = float(c[1]), c010 = float(c[sy]), c110 = float(c[sy + 1]);
      const float c001 = float(c[sz]), c101 = float(c[sz + 1]), c011 = float(c[sy + sz]), c111 = float(c[sy + sz + 1]);
      const float c00 = c000 + f[0] * (c100 - c000), c10 = c010 + f[0] * (c110 - c010);
      const float c01 = c001 + f[0] * (c101 - c001), c11 = c011 + f[0] * (c111 - c011);
      const float c0 = c00 + f[1] * (c10 - c00), c1 = c01 + f[1] * (c11 - c01);
      return c0 + f[2] * (c1 - c0);
    }
  }
}

/// Adds a block's values to the totals: one atomic per block.
__device__ void block_total(double sum, unsigned long long count, double* total, unsigned long long* lookups) {
  for (int o = 16; o > 0; o >>= 1) {
    sum += __shfl_down_sync(0xffffffffu, sum, o);
    count += __shfl_down_sync(0xffffffffu, count, o);
  }
  __shared__ double s_sum[32];
  __shared__ unsigned long long s_count[32];
  const int lane = threadIdx.x % 32, warp = threadIdx.x / 32;
  if (lane == 0) {
    s_sum[warp] = sum;
    s_count[warp] = count;
  }
  __syncthreads();
  if (threadIdx.x == 0) {
    double bs = 0;
    unsigned long long bc = 0;
    for (int w = 0; w < int(blockDim.x + 31) / 32; ++w) {
      bs += s_sum[w];
      bc += s_count[w];
    }
    atomicAdd(total, bs);
    atomicAdd(lookups, bc);
  }
}

constexpr int kBlock = 256;

/// random: `per_thread` lookups per thread at uniformly random points of the box.
template <Arith A, class T>
__global__ void __launch_bounds__(kBlock) random_points(Grid<T> g, int per_thread, double* total,
                                                        unsigned long long* lookups) {
  std::uint32_t rng = d_ray_seed(blockIdx.x * blockDim.x + threadIdx.x);
  const float hx = float(g.n[0] - 1), hy = float(g.n[1] - 1), hz = float(g.n[2] - 1);
  float sum = 0;
  for (int k = 0; k < per_thread; ++k) {
    const float x = d_unit_open0(d_next_u32(rng)) * hx, y = d_unit_open0(d_next_u32(rng)) * hy;
    const float z = d_unit_open0(d_next_u32(rng)) * hz;
    sum += lookup<A>(g, x, y, z);
  }
  block_total(double(sum), static_cast<unsigned long long>(per_thread), total, lookups);
}

/// march: each ray of the camera through the whole box at half-voxel steps.
template <Arith A, class T>
__global__ void __launch_bounds__(kBlock) march(Grid<T> g, const Ray* __restrict__ rays, int nrays, double* total,
                                                unsigned long long* lookups) {
  const int r = blockIdx.x * blockDim.x + threadIdx.x;
  float sum = 0;
  unsigned long long count = 0;
  if (r < nrays) {
    const Ray ray = rays[r];
    for (float t = ray.t0; t < ray.t1; t += 0.5f) {
      sum += lookup<A>(g, ray.o[0] + t * ray.d[0], ray.o[1] + t * ray.d[1], ray.o[2] + t * ray.d[2]);
      ++count;
    }
  }
  block_total(double(sum), count, total, lookups);
}

/// delta: lookup_limit's loop (exponential steps against the constant majorant, the opacity
/// table, a ray ends at a real collision), the same random numbers per ray.
template <Arith A, class T>
__global__ void __launch_bounds__(kBlock) delta(Grid<T> g, const Ray* __restrict__ rays, int nrays,
                                                const float* __restrict__ sigma, float tf_lo, float scale,
                                                float majorant, double* total, unsigned long long* lookups) {
  const int r = blockIdx.x * blockDim.x + threadIdx.x;
  double sum = 0;
  unsigned long long count = 0;
  if (r < nrays) {
    const Ray ray = rays[r];
    std::uint32_t rng = d_ray_seed(std::uint32_t(r));
    const float inv_maj = 1.0f / majorant;
    float t = ray.t0;
    for (;;) {
      t -= logf(d_unit_open0(d_next_u32(rng))) * inv_maj;
      if (!(t < ray.t1)) break;
      const float value = lookup<A>(g, ray.o[0] + t * ray.d[0], ray.o[1] + t * ray.d[1], ray.o[2] + t * ray.d[2]);
      const float x = fminf(fmaxf((value - tf_lo) * scale, 0.0f), float(kTableSize));
      const int b = min(int(x), kTableSize - 1);
      const float s = sigma[b] + (x - float(b)) * (sigma[b + 1] - sigma[b]);
      ++count;
      sum += s;
      if (d_unit_open0(d_next_u32(rng)) * majorant < s) break;  // a real collision
    }
  }
  block_total(sum, count, total, lookups);
}

// ---------------------------------------------------------------------------------------------
// Host side
// ---------------------------------------------------------------------------------------------

struct Args {
  std::vector<int> sizes = {128, 256};
  int threads_total = 1 << 20, per_thread = 64, rays_side = 1024, reps = 5, device = 0;
  std::string raw, raw_dtype, csv;
  int dims[3] = {0, 0, 0};
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto need = [&](int n) {
      if (i + n >= argc) {
        std::fprintf(stderr, "%s needs %d value(s)\n", s.c_str(), n);
        std::exit(2);
      }
    };
    if (s == "--sizes") {
      need(1);
      a.sizes.clear();
      for (std::string v = argv[++i]; !v.empty();) {
        const auto comma = v.find(',');
        a.sizes.push_back(std::atoi(v.substr(0, comma).c_str()));
        v = comma == std::string::npos ? "" : v.substr(comma + 1);
      }
    } else if (s == "--threads-total") {
      need(1);
      a.threads_total = std::atoi(argv[++i]);
    } else if (s == "--per-thread") {
      need(1);
      a.per_thread = std::atoi(argv[++i]);
    } else if (s == "--rays-side") {
      need(1);
      a.rays_side = std::atoi(argv[++i]);
    } else if (s == "--reps") {
      need(1);
      a.reps = std::atoi(argv[++i]);
    } else if (s == "--device") {
      need(1);
      a.device = std::atoi(argv[++i]);
    } else if (s == "--raw") {
      need(5);
      a.raw = argv[++i];
      for (int& d : a.dims) d = std::atoi(argv[++i]);
      a.raw_dtype = argv[++i];
    } else if (s == "--csv") {
      need(1);
      a.csv = argv[++i];
    } else {
      std::fprintf(stderr, "unknown argument %s (see the header of bench/lookup/lookup_cuda.cu)\n", s.c_str());
      std::exit(2);
    }
  }
  for (int n : a.sizes)
    if (n < 4 || n > 1024) {
      std::fprintf(stderr, "--sizes: each edge in [4, 1024] (got %d)\n", n);
      std::exit(2);
    }
  if (a.threads_total < kBlock || a.per_thread < 1 || a.rays_side < 16 || a.reps < 1) {
    std::fprintf(stderr, "need --threads-total >= %d, --per-thread >= 1, --rays-side >= 16, --reps >= 1\n", kBlock);
    std::exit(2);
  }
  return a;
}

/// --raw's volume as float32 values (int16 and uint8 exactly)
lookup_bench::Volume load_raw(const Args& a) {
  lookup_bench::Volume v;
  v.nx = a.dims[0];
  v.ny = a.dims[1];
  v.nz = a.dims[2];
  if (v.nx < 2 || v.ny < 2 || v.nz < 2) throw std::runtime_error("--raw: dims must be >= 2");
  const std::size_t n = std::size_t(v.nx) * v.ny * v.nz;
  const std::size_t size = a.raw_dtype == "int16" ? 2 : a.raw_dtype == "uint8" ? 1 : a.raw_dtype == "float32" ? 4 : 0;
  if (size == 0) throw std::runtime_error("--raw dtype must be int16, uint8 or float32");
  std::vector<char> bytes(n * size);
  std::ifstream in(a.raw, std::ios::binary);
  if (!in || !in.read(bytes.data(), std::streamsize(bytes.size()))) throw std::runtime_error("cannot read " + a.raw);
  v.data.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (size == 2) {
      std::int16_t x;
      std::memcpy(&x, &bytes[2 * i], 2);
      v.data[i] = x;
    } else if (size == 1) {
      v.data[i] = static_cast<unsigned char>(bytes[i]);
    } else {
      std::memcpy(&v.data[i], &bytes[4 * i], 4);
    }
  }
  v.name = a.raw;
  return v;
}

template <class T>
struct DeviceArray {
  T* p = nullptr;
  std::size_t n = 0;
  explicit DeviceArray(const std::vector<T>& h) : n(h.size()) {
    check(cudaMalloc(&p, n * sizeof(T)), "cudaMalloc");
    check(cudaMemcpy(p, h.data(), n * sizeof(T), cudaMemcpyHostToDevice), "cudaMemcpy");
  }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
  ~DeviceArray() { cudaFree(p); }
};

/// The float32 volume in a 3-D texture with hardware trilinear filtering.
struct Texture {
  cudaArray_t array = nullptr;
  cudaTextureObject_t tex = 0;
  explicit Texture(const lookup_bench::Volume& v) {
    const cudaChannelFormatDesc fmt = cudaCreateChannelDesc<float>();
    const cudaExtent ext = make_cudaExtent(std::size_t(v.nx), std::size_t(v.ny), std::size_t(v.nz));
    check(cudaMalloc3DArray(&array, &fmt, ext), "cudaMalloc3DArray");
    cudaMemcpy3DParms cp{};
    cp.srcPtr = make_cudaPitchedPtr(const_cast<float*>(v.data.data()), std::size_t(v.nx) * sizeof(float),
                                    std::size_t(v.nx), std::size_t(v.ny));
    cp.dstArray = array;
    cp.extent = ext;
    cp.kind = cudaMemcpyHostToDevice;
    check(cudaMemcpy3D(&cp), "cudaMemcpy3D");
    cudaResourceDesc res{};
    res.resType = cudaResourceTypeArray;
    res.res.array.array = array;
    cudaTextureDesc td{};
    for (auto& m : td.addressMode) m = cudaAddressModeClamp;
    td.filterMode = cudaFilterModeLinear;
    td.readMode = cudaReadModeElementType;
    td.normalizedCoords = 0;
    check(cudaCreateTextureObject(&tex, &res, &td, nullptr), "cudaCreateTextureObject");
  }
  Texture(const Texture&) = delete;
  Texture& operator=(const Texture&) = delete;
  ~Texture() {
    cudaDestroyTextureObject(tex);
    cudaFreeArray(array);
  }
};

struct Row {
  std::string field, dtype, pattern, arith;
  unsigned long long lookups = 0;
  double seconds = 0, checksum = 0;
  int regs = 0;
  std::size_t local_bytes = 0;
};

struct Totals {
  double* sum = nullptr;
  unsigned long long* count = nullptr;
  Totals() {
    check(cudaMalloc(&sum, sizeof(double)), "cudaMalloc");
    check(cudaMalloc(&count, sizeof(unsigned long long)), "cudaMalloc");
  }
  Totals(const Totals&) = delete;
  Totals& operator=(const Totals&) = delete;
  ~Totals() {
    cudaFree(sum);
    cudaFree(count);
  }
};

/// Times `launch` (best of reps after one untimed launch) and reads the totals of the last one.
template <class Kernel, class Launch>
Row time_kernel(Kernel kernel, Launch launch, int reps, Totals& tot) {
  Row row;
  cudaFuncAttributes attr{};
  check(cudaFuncGetAttributes(&attr, kernel), "cudaFuncGetAttributes");
  row.regs = attr.numRegs;
  row.local_bytes = attr.localSizeBytes;
  cudaEvent_t e0, e1;
  check(cudaEventCreate(&e0), "cudaEventCreate");
  check(cudaEventCreate(&e1), "cudaEventCreate");
  double best = 1e300;
  for (int rep = -1; rep < reps; ++rep) {
    check(cudaMemset(tot.sum, 0, sizeof(double)), "cudaMemset");
    check(cudaMemset(tot.count, 0, sizeof(unsigned long long)), "cudaMemset");
    check(cudaEventRecord(e0), "cudaEventRecord");
    launch();
    check(cudaGetLastError(), "kernel launch");
    check(cudaEventRecord(e1), "cudaEventRecord");
    check(cudaEventSynchronize(e1), "kernel");
    float ms = 0;
    check(cudaEventElapsedTime(&ms, e0, e1), "cudaEventElapsedTime");
    if (rep >= 0) best = std::min(best, 1e-3 * ms);
  }
  cudaEventDestroy(e0);
  cudaEventDestroy(e1);
  check(cudaMemcpy(&row.checksum, tot.sum, sizeof(double), cudaMemcpyDeviceToHost), "cudaMemcpy");
  check(cudaMemcpy(&row.lookups, tot.count, sizeof(unsigned long long), cudaMemcpyDeviceToHost), "cudaMemcpy");
  row.seconds = best;
  return row;
}

/// Every pattern and arithmetic on one field of T.
template <class T>
void run_field(const Args& a, const lookup_bench::Volume& vol, const std::string& name, const char* dtype,
               const lookup_bench::Setup& big, const lookup_bench::Setup& small, std::vector<Row>& rows) {
  std::vector<T> host(vol.data.size());
  for (std::size_t i = 0; i < host.size(); ++i) host[i] = T(std::is_integral_v<T> ? std::lround(vol.data[i]) : vol.data[i]);
  const DeviceArray<T> field(host);
  Grid<T> g{field.p, 0, {vol.nx, vol.ny, vol.nz}, vol.nx, static_cast<long long>(vol.nx) * vol.ny};
  std::unique_ptr<Texture> tex;
  if constexpr (std::is_same_v<T, float>) {
    tex = std::make_unique<Texture>(vol);
    g.tex = tex->tex;
  }
  const DeviceArray<Ray> rays(big.rays), rays_small(small.rays);
  const DeviceArray<float> sigma(big.sigma);
  const float scale = float(kTableSize) / (big.tf_hi - big.tf_lo);
  Totals tot;
  const int blocks_random = a.threads_total / kBlock;
  const int nrays = int(big.rays.size()), nsmall = int(small.rays.size());
  const int blocks_rays = (nrays + kBlock - 1) / kBlock, blocks_small = (nsmall + kBlock - 1) / kBlock;

  auto all = [&]<Arith A>(const char* arith) {
    auto add = [&](Row r, const char* pattern) {
      r.field = name;
      r.dtype = dtype;
      r.pattern = pattern;
      r.arith = arith;
      std::printf("  %-28s %-7s %-6s %-6s %13llu lookups %9.3f ms %8.2f G lookups/s  %3d regs %5zu B local  checksum %.6g\n",
                  r.field.c_str(), r.dtype.c_str(), r.pattern.c_str(), r.arith.c_str(), r.lookups, 1e3 * r.seconds,
                  double(r.lookups) / r.seconds * 1e-9, r.regs, r.local_bytes, r.checksum);
      std::fflush(stdout);
      rows.push_back(r);
    };
    add(time_kernel(random_points<A, T>,
                    [&] { random_points<A, T><<<blocks_random, kBlock>>>(g, a.per_thread, tot.sum, tot.count); },
                    a.reps, tot),
        "random");
    add(time_kernel(march<A, T>, [&] { march<A, T><<<blocks_rays, kBlock>>>(g, rays.p, nrays, tot.sum, tot.count); },
                    a.reps, tot),
        "march");
    add(time_kernel(delta<A, T>,
                    [&] {
                      delta<A, T><<<blocks_rays, kBlock>>>(g, rays.p, nrays, sigma.p, big.tf_lo, scale, big.majorant,
                                                           tot.sum, tot.count);
                    },
                    a.reps, tot),
        "delta");
    // The CPU's loop on the same first rays: its count and checksum beside the GPU's
    if constexpr (A == Arith::Float) {
      const Row r = time_kernel(delta<A, T>,
                                [&] {
                                  delta<A, T><<<blocks_small, kBlock>>>(g, rays_small.p, nsmall, sigma.p, small.tf_lo,
                                                                        scale, small.majorant, tot.sum, tot.count);
                                },
                                1, tot);
      lookup_bench::Volume as_read = vol;
      for (std::size_t i = 0; i < host.size(); ++i) as_read.data[i] = float(host[i]);
      const auto cpu = lookup_bench::run(lookup_bench::Variant::ScalarFloat, as_read, small);
      std::printf("  %-28s %-7s check: delta on the first %d rays, GPU float %llu lookups, checksum %.7g; "
                  "CPU scalar-float %llu, %.7g\n",
                  name.c_str(), dtype, nsmall, r.lookups, r.checksum, static_cast<unsigned long long>(cpu.lookups),
                  cpu.checksum);
    }
  };
  all.template operator()<Arith::Kernel>("kernel");
  all.template operator()<Arith::Float>("float");
  if constexpr (std::is_same_v<T, float>) all.template operator()<Arith::Tex>("tex");
}

}  // namespace

int main(int argc, char** argv) try {
  const Args a = parse(argc, argv);
  int ndev = 0;
  if (cudaGetDeviceCount(&ndev) != cudaSuccess || ndev == 0) {
    std::fprintf(stderr, "lookup_cuda: no CUDA device (%d visible); nothing measured\n", ndev);
    return 77;
  }
  check(cudaSetDevice(a.device), "cudaSetDevice");
  cudaDeviceProp prop{};
  check(cudaGetDeviceProperties(&prop, a.device), "cudaGetDeviceProperties");
  std::printf("lookup_cuda: %s, %d SMs, %.1f GiB, L2 %.0f MiB; random: %d threads x %d lookups; rays %d x %d\n",
              prop.name, prop.multiProcessorCount, double(prop.totalGlobalMem) / (1 << 30),
              double(prop.l2CacheSize) / (1 << 20), a.threads_total, a.per_thread, a.rays_side, a.rays_side);
  std::vector<lookup_bench::Volume> vols;
  for (int n : a.sizes) {
    vols.push_back(lookup_bench::synthetic_volume(n));
    vols.back().name = "synthetic " + std::to_string(n) + "^3";
  }
  if (!a.raw.empty()) vols.push_back(load_raw(a));
  std::vector<Row> rows;
  for (const auto& vol : vols) {
    // lookup_limit's rays and opacity table (default ramp); the small set is lookup_limit's 65,536 rays
    const auto big = lookup_bench::make_setup(vol, a.rays_side * a.rays_side, 0.75f, 0.9f);
    const auto small = lookup_bench::make_setup(vol, 1 << 16, 0.75f, 0.9f);
    run_field<float>(a, vol, vol.name, "float32", big, small, rows);
    run_field<std::int16_t>(a, vol, vol.name, "int16", big, small, rows);
  }
  if (!a.csv.empty()) {
    std::FILE* f = std::fopen(a.csv.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + a.csv);
    std::fprintf(f, "device,field,dtype,pattern,arith,lookups,seconds,glookups_per_s,registers,local_bytes,checksum\n");
    for (const Row& r : rows)
      std::fprintf(f, "%s,%s,%s,%s,%s,%llu,%.6g,%.6g,%d,%zu,%.9g\n", prop.name, r.field.c_str(), r.dtype.c_str(),
                   r.pattern.c_str(), r.arith.c_str(), r.lookups, r.seconds, double(r.lookups) / r.seconds * 1e-9,
                   r.regs, r.local_bytes, r.checksum);
    std::fclose(f);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "lookup_cuda: %s\n", e.what());
  return 1;
}
