#pragma once
/// A mesh's arrays in GPU memory (docs/gpu.md): Tessera checks a curvilinear or unstructured
/// mesh's elements and builds its location tables on the host, so each of a domain's arrays
/// that is device memory (cudaMemoryTypeDevice; managed memory is readable on the host and
/// never copied) is copied to the host first, within the memory limit, and the domain pointed
/// at the copy. A render on the GPU then reads those arrays where they were, on the device.
#include "data/device_arrays.h"

#include <tessera/mesh.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tessera::insitu {

/// Where a mesh's arrays live, from one question to the CUDA runtime per array.
struct MeshMemory {
  bool gpu_readable = false;                              ///< some array is device or managed memory
  std::vector<std::array<char, kMeshArraySlots>> device;  ///< per domain and slot: 1 where device memory
  bool on_device() const;
  /// Every array of `m` (the mesh this was asked of) is device memory.
  bool all_device(const Mesh& m) const;
};
/// Of `m`, whose descriptors check_mesh_descriptors accepted.
MeshMemory mesh_memory(const Mesh& m);

/// Copies each domain's device arrays (`where`: mesh_memory(m)) to host buffers kept in `out`
/// and points the domain at them, each original kept as its MeshDomain::device_copy (a
/// render on the GPU reads it there, not a copy of the copy): afterwards nothing the CPU reads
/// of `m` is device memory. Arrays of one
/// domain whose byte spans overlap or touch (x, y and z interleaved) are copied once, as one
/// span. The bytes are checked against `limit_bytes` before anything is allocated: over it,
/// std::runtime_error naming the bytes and `limit_text`; CUDA failures (a pointer that is not
/// an allocation of that size) throw as cuda_copy_to_host does. `stream`: the simulation's
/// CUDA stream (null: the whole device).
void stage_mesh_to_host(Mesh& m, const MeshMemory& where, HostStaging& out, void* stream, std::uint64_t limit_bytes,
                        const std::string& limit_text);

}  // namespace tessera::insitu
