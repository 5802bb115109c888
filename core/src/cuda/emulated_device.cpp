/// The host emulation of a GPU (emulated_device.h).
#include "cuda/emulated_device.h"

#include "cuda/device_value_dispatch.h"
#include "cuda/pixel_kernel.h"
#include "kernels/emulated_slice.h"
#include "kernels/lane_kernel.h"
#include "kernels/wave_scratch.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace tessera::cuda {

// Instantiated beside the CPU's kernels (kernels/tile_kernel_<value>.cpp)
extern template void emulate_slice<std::uint8_t>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<std::int16_t>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<std::uint16_t>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<double>(const SliceArgs&, LaneLoop, const WaveTuning&);
#if defined(TESSERA_CUDA_FLOAT32)
extern template void emulate_slice<float>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<Rectilinear<float>>(const SliceArgs&, LaneLoop, const WaveTuning&);
#endif
extern template void emulate_slice<Rectilinear<std::uint8_t>>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<Rectilinear<std::int16_t>>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<Rectilinear<std::uint16_t>>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<Rectilinear<double>>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<MagnitudeValue>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<Rectilinear<MagnitudeValue>>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<AmrValue>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<MeshValue>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<PagedValue>(const SliceArgs&, LaneLoop, const WaveTuning&);
extern template void emulate_slice<Rectilinear<PagedValue>>(const SliceArgs&, LaneLoop, const WaveTuning&);

namespace {

/// What fresh emulated device memory holds: neither zero nor a plausible double
constexpr unsigned char kGarbage = 0xA5;
constexpr std::size_t kAlign = 256;

class EmulatedBackend final : public DeviceBackend {
 public:
  explicit EmulatedBackend(EmulatedDevice d) : m_d(std::move(d)) {}
  ~EmulatedBackend() override {
    for (auto& [p, bytes] : m_live) ::operator delete (p, std::align_val_t{kAlign});
  }

  std::string name() const override { return m_d.name; }
  MemoryKind memory_kind(const void* p) const override {
    const std::lock_guard lock(m_mutex);
    const auto* q = static_cast<const unsigned char*>(p);
    for (const auto& [base, bytes] : m_d.device_ranges) {
      const auto* b = static_cast<const unsigned char*>(base);
      if (q >= b && q < b + bytes) return MemoryKind::Device;
    }
    return MemoryKind::Host;
  }
  void memory_info(std::size_t* free_bytes, std::size_t* total_bytes) const override {
    const std::lock_guard lock(m_mutex);
    *total_bytes = m_d.memory_bytes;
    *free_bytes = m_d.memory_bytes > m_held ? m_d.memory_bytes - m_held : 0;
  }

  void* allocate(std::size_t bytes, const std::string& what) override {
    const std::size_t n = bytes > 0 ? bytes : 1;
    {
      const std::lock_guard lock(m_mutex);
      if (n > m_d.memory_bytes - std::min(m_held, m_d.memory_bytes))
        throw std::runtime_error("emulated device: allocation of " + what + ", " + std::to_string(bytes) +
                                 " bytes, exceeds its free memory");
    }
    void* p = ::operator new (n, std::align_val_t{kAlign});
    std::memset(p, kGarbage, n);
    const std::lock_guard lock(m_mutex);
    m_live[p] = n;
    m_held += n;
    return p;
  }
  void release(void* p) noexcept override {
    if (!p) return;
    {
      const std::lock_guard lock(m_mutex);
      const auto it = m_live.find(p);
      if (it == m_live.end()) return;
      m_held -= it->second;
      m_live.erase(it);
    }
    ::operator delete (p, std::align_val_t{kAlign});
  }
  void copy_to_device(void* dst, const void* src, std::size_t bytes, const std::string&) override {
    if (bytes) std::memcpy(dst, src, bytes);
  }
  void copy_to_host(void* dst, const void* src, std::size_t bytes, const std::string&) override {
    if (bytes) std::memcpy(dst, src, bytes);
  }
  void zero(void* dst, std::size_t bytes, const std::string&) override {
    if (bytes) std::memset(dst, 0, bytes);
  }
  void copy_on_device(void* dst, const void* src, std::size_t bytes, const std::string&) override {
    if (bytes) std::memcpy(dst, src, bytes);
  }

  void wait_for_caller(void*) override {}
  void widen_float32(const unsigned char* src, const std::int64_t dims[3], const std::int64_t byte_strides[3],
                     double* dst) override {
    std::int64_t q = 0;
    for (std::int64_t k = 0; k < dims[2]; ++k)
      for (std::int64_t j = 0; j < dims[1]; ++j)
        for (std::int64_t i = 0; i < dims[0]; ++i) {
          float v;
          std::memcpy(&v, src + i * byte_strides[0] + j * byte_strides[1] + k * byte_strides[2], sizeof v);
          dst[q++] = static_cast<double>(v);
        }
  }
  void run_slice(const KernelScene& ks, const SliceArgs& a, int, const std::string& what) override {
    if (!with_device_value(ks,
                           [&](auto tag) { emulate_slice<typename decltype(tag)::type>(a, m_d.lane_loop, m_d.wave); }))
      throw std::invalid_argument("emulated device: no kernel for " + what);
    if (m_d.after_slice) m_d.after_slice(++m_slices);
  }
  std::size_t slice_scratch_bytes(const KernelScene& ks, std::int64_t threads) const override {
    return m_d.lane_loop == LaneLoop::Wavefront && wave_applies(ks) ? wave_scratch_bytes(threads, m_d.wave.slots) : 0;
  }
  void merge_lanes(PixelSums* px, AuxSums* aux, const PixelSums* lane_px, const AuxSums* lane_aux, std::int64_t njobs,
                   int lanes) override {
    tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, njobs), [&](const tbb::blocked_range<std::int64_t>& r) {
      for (std::int64_t j = r.begin(); j < r.end(); ++j) merge_pixel(px, aux, lane_px, lane_aux, j, lanes);
    });
  }
  bool covers(const KernelScene& ks, std::string* why) const override {
    if (with_device_value(ks, [](auto) {})) return true;
    return device_value_supported(ks, why);  // false, naming what
  }

  void declare(const void* p, std::size_t bytes) {
    const std::lock_guard lock(m_mutex);
    m_d.device_ranges.emplace_back(p, bytes);
  }
  void copy_out(const void* src, const char* what) const {
    if (m_d.copy_out_fault && m_d.copy_out_fault(src, what))
      throw std::runtime_error(std::string(what) + ": an illegal memory access (emulated copy fault)");
  }
  void forget(const void* p) {
    const std::lock_guard lock(m_mutex);
    std::erase_if(m_d.device_ranges, [&](const auto& r) { return r.first == p; });
  }

  std::size_t held() const {
    const std::lock_guard lock(m_mutex);
    return m_held;
  }

 private:
  EmulatedDevice m_d;
  mutable std::mutex m_mutex;  // guards m_live, m_held and m_d.device_ranges
  std::map<void*, std::size_t> m_live;
  std::size_t m_held = 0;
  std::atomic<std::int64_t> m_slices{0};  ///< slices run (after_slice's count)
};

}  // namespace

std::shared_ptr<DeviceBackend> emulated_backend(EmulatedDevice d) {
  return std::make_shared<EmulatedBackend>(std::move(d));
}

namespace {
/// b as the emulation (B: DeviceBackend or const DeviceBackend), or an error naming `what`.
template <class B>
auto& emulated(B& b, const char* what) {
  using E = std::conditional_t<std::is_const_v<B>, const EmulatedBackend, EmulatedBackend>;
  auto* e = dynamic_cast<E*>(&b);
  if (!e) throw std::invalid_argument(std::string(what) + ": not an emulated backend");
  return *e;
}
}  // namespace

std::size_t emulated_bytes_held(const DeviceBackend& b) { return emulated(b, "emulated_bytes_held").held(); }

void emulated_declare_device_memory(DeviceBackend& b, const void* p, std::size_t bytes) {
  emulated(b, "emulated_declare_device_memory").declare(p, bytes);
}

void emulated_forget_device_memory(DeviceBackend& b, const void* p) {
  emulated(b, "emulated_forget_device_memory").forget(p);
}

void emulated_copy_out(const DeviceBackend& b, const void* src, const char* what) {
  emulated(b, "emulated_copy_out").copy_out(src, what);
}

}  // namespace tessera::cuda
