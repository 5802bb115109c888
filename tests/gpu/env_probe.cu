// probe_environment_on_device (env_probe.h): the background's lookups on the GPU.
#include "env_probe.h"

#if defined(__CUDA_ARCH__)
#include "lights/environment_eval.h"  // the device's definitions, as the backend's kernels have them
#endif

#include <cuda_runtime.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace gpu_test {

namespace {

__global__ void probe_kernel(const tessera::Environment* env, EnvProbe* p, int n) {
  const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (i < n) run_probe(*env, p[i]);
}

__global__ void dist_kernel(const double* t, std::size_t bins, DistProbe* p, int n) {
  const int i = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (i < n) run_probe(tessera::detail::distribution_at(t, bins), p[i]);
}

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("probe_environment_on_device: ") + what + ": " + cudaGetErrorString(e));
}

/// Device memory freed when the probe returns or throws.
struct DeviceFree {
  void operator()(void* p) const { cudaFree(p); }
};
using DeviceBytes = std::unique_ptr<void, DeviceFree>;

/// A device copy of `bytes` at `src` (null for none).
DeviceBytes to_device(const void* src, std::size_t bytes, const char* what) {
  if (bytes == 0) return nullptr;
  void* d = nullptr;
  check(cudaMalloc(&d, bytes), what);
  DeviceBytes owned(d);
  check(cudaMemcpy(d, src, bytes, cudaMemcpyHostToDevice), what);
  return owned;
}

}  // namespace

std::vector<EnvProbe> probe_environment_on_device(const tessera::Environment& env, std::span<const EnvProbe> in) {
  const auto texels = env.texels();
  const auto table = env.distribution_table();
  const DeviceBytes d_tex = to_device(texels.data(), texels.size_bytes(), "texels");
  const DeviceBytes d_tab = to_device(table.data(), table.size_bytes(), "table");
  const tessera::Environment moved =
      env.relocated(static_cast<const tessera::Color*>(d_tex.get()), static_cast<const double*>(d_tab.get()));
  const DeviceBytes d_env = to_device(&moved, sizeof(moved), "environment");
  const DeviceBytes d_p = to_device(in.data(), in.size_bytes(), "probes");
  const int n = static_cast<int>(in.size());
  probe_kernel<<<(n + 127) / 128, 128>>>(static_cast<const tessera::Environment*>(d_env.get()),
                                         static_cast<EnvProbe*>(d_p.get()), n);
  check(cudaGetLastError(), "launch");
  std::vector<EnvProbe> out(in.size());
  check(cudaMemcpy(out.data(), d_p.get(), in.size_bytes(), cudaMemcpyDeviceToHost), "results");
  return out;
}

std::vector<DistProbe> probe_distribution_on_device(std::span<const double> table, std::size_t bins,
                                                    std::span<const DistProbe> in) {
  const DeviceBytes d_tab = to_device(table.data(), table.size_bytes(), "table");
  const DeviceBytes d_p = to_device(in.data(), in.size_bytes(), "probes");
  const int n = static_cast<int>(in.size());
  dist_kernel<<<(n + 127) / 128, 128>>>(static_cast<const double*>(d_tab.get()), bins, static_cast<DistProbe*>(d_p.get()),
                                        n);
  check(cudaGetLastError(), "launch");
  std::vector<DistProbe> out(in.size());
  check(cudaMemcpy(out.data(), d_p.get(), in.size_bytes(), cudaMemcpyDeviceToHost), "results");
  return out;
}

}  // namespace gpu_test
