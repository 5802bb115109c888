#pragma once
/// A mesh whose arrays are GPU memory, checked and summarised where they are (Mesh::device,
/// mesh.h; docs/gpu.md, "Meshes in device memory"): what prepare() reads of such a mesh once
/// its layout is reused (the layout is built on the host, from the geometry of an earlier
/// call). Each entry runs one pass per domain over its cells or values with the per-item code
/// the host's build runs (mesh/element_indices.h, mesh/element_range.h), folds the results
/// with min / max / or / sums (no order, so the same bits as the host), and brings back only
/// the fold: a fault's element, the macrocells, a few totals.
///
/// Where: on the CUDA device that holds the arrays (mesh_device_cuda.cu), after the work
/// queued on `stream` (null: the whole device); on the installed host emulation of a GPU
/// (gpu_emulation.h), by the host loops below. In a build without CUDA and no emulation they
/// throw std::runtime_error saying so. CUDA failures throw CudaError naming the call.
#include <tessera/field_summary.h>
#include <tessera/math.h>
#include <tessera/mesh.h>

#include "mesh/element_range.h"
#include "mesh/geometry_hash.h"

#include <cstdint>

namespace tessera::cuda {

/// The first real cell (lowest domain, then lowest cell) that check_mesh_indices refuses, and
/// the real cells counted.
struct MeshIndexFault {
  std::int64_t domain = -1;  ///< -1: no fault
  std::int64_t cell = -1;
  int corner = -1;
  std::int64_t index = 0;  ///< its vertex index (outside the count, or of a non-finite vertex)
  Vec3 vertex{0.0};        ///< that vertex, when its index is inside
  std::uint64_t real_cells = 0;
};

/// The values of every domain: NaN count, count, the min / max of the finite ones (zeros as
/// +0.0) and the flags (MeshTables' totals, ghosts' values included), and the finite min / max
/// with ghost cells' values left out for cell data (the adapter's `range: auto`).
struct MeshValueStats {
  std::uint64_t nan = 0, values = 0;
  ElementRange all;
  ElementRange real;
};

/// check_mesh_indices' element pass (the descriptors are checked on the host first).
MeshIndexFault mesh_index_fault(const Mesh& mesh, void* stream);
MeshValueStats mesh_value_stats(const Mesh& mesh, void* stream);
/// mesh_summary's macrocells (lo, hi, flags; nothing else of Parts) over grid `g` from every
/// real cell's box (element_box) and value range: what mesh_summary gives for the layout of
/// the same geometry.
FieldSummary::Parts mesh_summary_cells(const Mesh& mesh, const MacroGrid& g, void* stream);
/// mesh/geometry_hash.h's item sums over every array of geometry_arrays(mesh).
GeometrySums mesh_geometry_sums(const Mesh& mesh, void* stream);

/// The same on the host, reading the arrays as host memory: the emulation's device, and the
/// reference the tests hold the device to.
MeshIndexFault mesh_index_fault_host(const Mesh& mesh);
MeshValueStats mesh_value_stats_host(const Mesh& mesh);
FieldSummary::Parts mesh_summary_cells_host(const Mesh& mesh, const MacroGrid& g);
GeometrySums mesh_geometry_sums_host(const Mesh& mesh);

}  // namespace tessera::cuda
