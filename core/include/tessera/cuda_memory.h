#pragma once
/// Copies out of device memory for the callers that must read a simulation's device array on
/// the host (the in situ adapter's staging when a render cannot read it in place, docs/gpu.md).
/// Declared in every build; without CUDA cuda_copy_to_host throws.
#include <tessera/field_view.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace tessera {

/// Copies `bytes` from `src` (device or managed memory) to `dst` (host memory), after the work
/// queued on `stream` (a cudaStream_t; null: after the whole device is synchronised); returns
/// when the copy is done. Throws tessera::cuda::CudaError (a std::runtime_error) naming the
/// call on a CUDA failure (a sticky one disables the GPU, cuda_disabled), std::runtime_error
/// in a build without CUDA or once the GPU is disabled.
void cuda_copy_to_host(void* dst, const void* src, std::size_t bytes, void* stream = nullptr);

/// Copies the elements of `box` (a validated view into device, managed or host memory; any
/// byte strides, negative ones included) to `dst` (host memory) densely, x fastest, each
/// element's bytes as they are: box.vertex_count() * dtype_size(box.dtype) bytes. Only those
/// bytes leave the device (packed there first), after the work queued on `stream` (null: the
/// whole device is synchronised first). What a distributed render copies of a device block
/// for the host side (other ranks' bricks, the brick cache). Throws as cuda_copy_to_host.
void cuda_copy_box_to_host(void* dst, const FieldView& box, void* stream = nullptr);

/// A field assembled in device memory (cuda_assemble_on_device): `view` is the dense global
/// field (x fastest) on the device, alive while `memory` (its owner) is; `bytes_to_device`:
/// what its host blocks' elements took from the host.
struct DeviceReplica {
  std::shared_ptr<const void> memory;
  FieldView view;
  std::uint64_t bytes_to_device = 0;
};

/// Assembles blocks of which at least one is device memory (`blocks[n]` placed at global
/// element `offsets[n]` of a field of `global` elements of `dtype`; the caller has checked
/// that they tile it) into one dense array on that device, after the work queued on `stream`:
/// what a render on the GPU reads in place, with nothing copied to the host. Device and
/// managed blocks are placed device to device (a kernel, any byte strides); host blocks are
/// copied to the host's place in the array (their elements only: x-contiguous rows straight
/// from the block, other layouts packed on the host first, one block at a time). The array's
/// bytes are checked against `limit_bytes` first (over it: std::runtime_error naming the
/// bytes and `limit_text`). Throws std::invalid_argument when no block is device memory or
/// blocks are on two devices, CudaError on a CUDA failure, std::runtime_error without CUDA.
DeviceReplica cuda_assemble_on_device(std::span<const FieldView> blocks,
                                      std::span<const std::array<std::int64_t, 3>> offsets,
                                      const std::int64_t global[3], DType dtype, void* stream,
                                      std::uint64_t limit_bytes, const std::string& limit_text);

}  // namespace tessera
