/// The CUDA DeviceBackend (cuda_backend.h): every runtime call through cuda_check, so a
/// failure names the call, and a sticky error disables the GPU for the process.
#include "cuda/cuda_backend.h"

#include "cuda/cuda_check.h"
#include "cuda/device_value_dispatch.h"
#include "cuda/pixel_kernel.h"
#include "cuda/widen_field.h"
#include "kernels/lane_loop.h"
#include "kernels/wave_scratch.h"

#include <cuda_runtime_api.h>

#include <cerrno>
#include <cstdlib>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace tessera::cuda {

namespace {

class CudaBackend final : public DeviceBackend {
 public:
  explicit CudaBackend(int device) : m_device(device) {
    cudaDeviceProp prop{};
    cuda_check(cudaGetDeviceProperties(&prop, device), "cudaGetDeviceProperties(" + std::to_string(device) + ")");
    m_name = prop.name;
  }

  std::string name() const override { return m_name; }
  MemoryKind memory_kind(const void* p) const override { return cuda_memory_kind(p); }
  void memory_info(std::size_t* free_bytes, std::size_t* total_bytes) const override {
    cuda_check(cudaMemGetInfo(free_bytes, total_bytes), "cudaMemGetInfo");
  }

  void* allocate(std::size_t bytes, const std::string& what) override {
    void* p = nullptr;
    cuda_check(cudaMalloc(&p, bytes > 0 ? bytes : 1), "cudaMalloc(" + what + ", " + std::to_string(bytes) + " bytes)");
    return p;
  }
  void release(void* p) noexcept override {
    if (!p) return;
    const DeviceGuard guard(m_device);
    cudaFree(p);  // an error here is not the caller's to see (the context may be gone)
  }
  void copy_to_device(void* dst, const void* src, std::size_t bytes, const std::string& what) override {
    cuda_check(cudaMemcpy(dst, src, bytes, cudaMemcpyHostToDevice),
               "cudaMemcpy(" + what + " to the device, " + std::to_string(bytes) + " bytes)");
  }
  void copy_to_host(void* dst, const void* src, std::size_t bytes, const std::string& what) override {
    cuda_check(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToHost), "cudaMemcpy(" + what + " to the host)");
  }
  void zero(void* dst, std::size_t bytes, const std::string& what) override {
    cuda_check(cudaMemset(dst, 0, bytes), "cudaMemset(" + what + ")");
  }
  void copy_on_device(void* dst, const void* src, std::size_t bytes, const std::string& what) override {
    cuda_check(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToDevice), "cudaMemcpy(" + what + " on the device)");
  }

  void wait_for_caller(void* stream) override {
    if (stream)
      cuda_check(cudaStreamSynchronize(static_cast<cudaStream_t>(stream)),
                 "cudaStreamSynchronize(the simulation's stream, before reading its arrays)");
    else cuda_check(cudaDeviceSynchronize(), "cudaDeviceSynchronize (before reading the field)");
  }
  void widen_float32(const unsigned char* src, const std::int64_t dims[3], const std::int64_t byte_strides[3],
                     double* dst) override {
    cuda::widen_float32(src, dims, byte_strides, dst);
  }
  void run_slice(const KernelScene& ks, const SliceArgs& a, int block_threads, const std::string& what) override {
    launch_pixel_slice(ks, a, block_threads);
    cuda_check(cudaDeviceSynchronize(), what);
  }
  std::size_t slice_scratch_bytes(const KernelScene& ks, std::int64_t threads) const override {
    return kDeviceLaneLoop == LaneLoop::Wavefront && wave_applies(ks)
               ? wave_scratch_bytes(threads, cuda_wave_tuning().slots)
               : 0;
  }
  void merge_lanes(PixelSums* px, AuxSums* aux, const PixelSums* lane_px, const AuxSums* lane_aux, std::int64_t njobs,
                   int lanes) override {
    cuda::merge_lanes(px, aux, lane_px, lane_aux, njobs, lanes);
  }
  bool covers(const KernelScene& ks, std::string* why) const override { return device_value_supported(ks, why); }

 private:
  int m_device;
  std::string m_name;
};

}  // namespace

std::shared_ptr<DeviceBackend> cuda_backend(int device) {
  static std::mutex mutex;
  static std::map<int, std::shared_ptr<DeviceBackend>> backends;
  const std::lock_guard lock(mutex);
  auto& b = backends[device];
  if (!b) b = std::make_shared<CudaBackend>(device);
  return b;
}

WaveTuning cuda_wave_tuning() {
  static const WaveTuning tuning = [] {
    const auto read = [](const char* name, long long lo, long long hi, long long fallback) {
      const char* v = std::getenv(name);
      if (!v || !*v) return fallback;
      char* end = nullptr;
      errno = 0;
      const long long x = std::strtoll(v, &end, 10);
      return errno == 0 && end && *end == '\0' && x >= lo && x <= hi ? x : fallback;
    };
    WaveTuning t;
    t.slots = read("TESSERA_CUDA_WAVE_SLOTS", 1, 1LL << 22, kWaveSlots);
    t.steps = static_cast<int>(read("TESSERA_CUDA_WAVE_STEPS", 1, 4096, kWaveSteps));
    return t;
  }();
  return tuning;
}

void launch_pixel_slice(const KernelScene& ks, const SliceArgs& a, int block_threads) {
  const std::int64_t n = (a.j1 - a.j0) * a.lanes;
  if (n <= 0 || a.k1 <= a.k0) return;
  if (block_threads < 32 || block_threads > kMaxBlockThreads) block_threads = 128;
  const auto blocks = static_cast<unsigned>((n + block_threads - 1) / block_threads);
#if defined(TESSERA_CUDA_WAVEFRONT)
  if (wave_applies(ks)) {
    if (!a.scratch) throw std::logic_error("wavefront slice without its path slots (SliceArgs::scratch)");
    with_device_value(ks, [&](auto tag) {
      using V = typename decltype(tag)::type;
#if defined(TESSERA_CUDA_AMR)
      launch_wave_slice<V>(a, static_cast<unsigned>(block_threads), cuda_wave_tuning());
#else
      if constexpr (!std::is_same_v<V, AmrValue>)
        launch_wave_slice<V>(a, static_cast<unsigned>(block_threads), cuda_wave_tuning());
#endif
    });
    return;
  }
#endif
  with_device_value(ks, [&](auto tag) {
    using V = typename decltype(tag)::type;
    // A CUDA kernel for refinement levels only with TESSERA_CUDA_AMR (device_value_supported
    // refuses them first otherwise)
#if defined(TESSERA_CUDA_AMR)
    launch_pixel_samples<V>(a, blocks, static_cast<unsigned>(block_threads));
#else
    if constexpr (!std::is_same_v<V, AmrValue>)
      launch_pixel_samples<V>(a, blocks, static_cast<unsigned>(block_threads));
#endif
  });
  cuda_check(cudaGetLastError(), "launch of " + pixel_kernel_name(ks) + " (" + std::to_string(blocks) + " blocks of " +
                                     std::to_string(block_threads) + " threads, samples " + std::to_string(a.k0) +
                                     " to " + std::to_string(a.k1 - 1) + " of each pixel in " +
                                     std::to_string(a.lanes) + " lanes)");
}

}  // namespace tessera::cuda
