#pragma once
/// DeviceBackend: what the host half of the GPU backend asks of a device (memory, copies, the
/// two kernels), so that the host half is written once and runs on two implementations:
/// - CUDA (cuda_backend.cpp, in a build with CUDA): the real device;
/// - the host emulation (emulated_device.h, every build): "device memory" is host memory and
///   the kernels' per-thread bodies (lane_kernel.h) run in a host loop.
/// The scene's device copies (device_scene.h), the slicing, the lanes, the memory limits and
/// the counters (device_render.h) are thereby tested in CI, on machines without a GPU.
/// Called per launch and per copy, never per sample: a virtual call costs nothing here.
#include <tessera/cuda_render.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace tessera {

struct KernelScene;
struct PixelSums;
struct AuxSums;

namespace cuda {

struct SliceArgs;

class DeviceBackend {
 public:
  virtual ~DeviceBackend() = default;

  /// The device's name (cudaDeviceProp::name), for messages and CudaTransfer.
  virtual std::string name() const = 0;
  /// Where `p`'s memory is as this device sees it: Device and Managed are read in place.
  virtual MemoryKind memory_kind(const void* p) const = 0;
  /// Free and total device memory in bytes.
  virtual void memory_info(std::size_t* free_bytes, std::size_t* total_bytes) const = 0;

  /// Device memory of `bytes` (at least 1) aligned to 256; throws naming `what` and the bytes.
  virtual void* allocate(std::size_t bytes, const std::string& what) = 0;
  /// Frees what allocate returned (null: nothing); errors are ignored (called while unwinding).
  virtual void release(void* p) noexcept = 0;
  virtual void copy_to_device(void* dst, const void* src, std::size_t bytes, const std::string& what) = 0;
  virtual void copy_to_host(void* dst, const void* src, std::size_t bytes, const std::string& what) = 0;
  virtual void zero(void* dst, std::size_t bytes, const std::string& what) = 0;
  /// Device memory to device memory (ranges that do not overlap).
  virtual void copy_on_device(void* dst, const void* src, std::size_t bytes, const std::string& what) = 0;

  /// Returns once the caller's queued work no longer writes its arrays: `stream` (a
  /// cudaStream_t) when given, else the whole device.
  virtual void wait_for_caller(void* stream) = 0;
  /// widen_float32 (widen_field.h) on this device; returns when done.
  virtual void widen_float32(const unsigned char* src, const std::int64_t dims[3], const std::int64_t byte_strides[3],
                             double* dst) = 0;
  /// One slice of the pixel kernel for `ks`'s Value (launch_pixel_slice, pixel_kernel.h);
  /// returns when it is done, throwing naming `what` when it failed.
  virtual void run_slice(const KernelScene& ks, const SliceArgs& a, int block_threads, const std::string& what) = 0;
  /// Device bytes run_slice needs in SliceArgs::scratch for slices of up to `threads` lanes of
  /// ks's Value (the wavefront loop's path slots, wave_scratch.h); 0: none.
  virtual std::size_t slice_scratch_bytes(const KernelScene& ks, std::int64_t threads) const = 0;
  /// merge_lanes (pixel_kernel.h) on this device; returns when done.
  virtual void merge_lanes(PixelSums* px, AuxSums* aux, const PixelSums* lane_px, const AuxSums* lane_aux,
                           std::int64_t njobs, int lanes) = 0;
  /// True when the device kernels cover ks's Value (device_value_supported); else *why says
  /// what is not covered.
  virtual bool covers(const KernelScene& ks, std::string* why) const = 0;
};

/// One allocation of a DeviceBackend, released when the object goes.
class BackendBuffer {
 public:
  explicit BackendBuffer(DeviceBackend& b) : m_b(&b) {}
  ~BackendBuffer() { m_b->release(m_ptr); }
  BackendBuffer(const BackendBuffer&) = delete;
  BackendBuffer& operator=(const BackendBuffer&) = delete;

  void allocate(std::size_t bytes, const std::string& what) {
    m_b->release(m_ptr);
    m_ptr = nullptr;
    m_bytes = 0;
    m_ptr = m_b->allocate(bytes, what);
    m_bytes = bytes;
  }
  /// Allocates `bytes` and copies them from host memory `src`; returns the bytes copied.
  std::size_t upload(const void* src, std::size_t bytes, const std::string& what) {
    allocate(bytes, what);
    if (bytes > 0) m_b->copy_to_device(m_ptr, src, bytes, what);
    return bytes;
  }
  void* get() const { return m_ptr; }
  template <class T>
  T* as() const {
    return static_cast<T*>(m_ptr);
  }
  std::size_t bytes() const { return m_bytes; }

 private:
  DeviceBackend* m_b;
  void* m_ptr = nullptr;
  std::size_t m_bytes = 0;
};

}  // namespace cuda
}  // namespace tessera
