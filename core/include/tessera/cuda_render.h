#pragma once
/// The CUDA backend's entry (docs/gpu.md): renders a prepared scene's tiles on a GPU with the
/// CPU's per-sample code (the kernel headers compile for both, host_device.h): the same
/// random streams as a function of (seed, frame, pixel, sample index), the same estimator.
/// A pixel's samples are drawn by up to 8 threads (sample lanes, a function of the image and
/// spp only), each adding its samples in index order, the lanes then added in lane order: the
/// sums differ from the CPU's by rounding only. Images agree with the CPU's within Monte Carlo
/// error (floating-point rounding and the device's math library differ), and on one GPU model
/// the bits are the same on every run, for any CudaLaunch and any split of the tiles.
///
/// Declared in every build: where Tessera was built without CUDA (TESSERA_CUDA=OFF, or no
/// nvcc found) cuda_built() is false, cuda_device_count() is 0 and render_tiles_cuda throws.
///
/// Covered: every dtype (uint8, int16, uint16, float32, float64) of a field in host memory
/// (copied once per prepared scene) or device / managed memory (read in place, any byte
/// strides), uniform and rectilinear axes, a vector's magnitude, vertex and cell data, uniform
/// sampling, every light kind, every background (an envmap's texels and sampling table are
/// copied with the scene), every integrator mode, denoiser features, adaptive sampling (the
/// CPU's counts, in two passes). Refused by name (std::invalid_argument): refinement levels
/// (not yet) and distributed hierarchies of them. Meshes and distributed (paged) fields are
/// covered: a paged field's bricks are copied to a bounded pool on the device as launches
/// miss them, a launch that missed one run again (device_bricks.h); the host cache's service
/// thread must run during the call, as for render_tiles.
///
/// The scene's device copies (field copy, majorants and every table) are made on a prepared
/// scene's first render_tiles_cuda and kept, on that device, until the prepared scene is
/// destroyed: later calls (the MPI scheduler's grabs of tiles) copy only the tiles'
/// pixel sums. A host field copied there is the caller's values at that first call: as for
/// the CPU, a prepared scene is valid only while the field's values are unchanged.
#include <tessera/field_summary.h>
#include <tessera/film.h>
#include <tessera/render.h>
#include <tessera/stats.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>

namespace tessera {

/// How render_tiles_cuda cuts its work into kernel launches, and what it may use. Launches are
/// bounded slices (some samples of some pixels each); the deadline (options.deadline) is
/// checked between them. The image does not depend on any of these numbers.
struct CudaLaunch {
  int device = 0;                      ///< CUDA device index (cudaSetDevice)
  int block_threads = 128;             ///< threads per block: one pixel each, in [32, 256]
  int samples_per_launch = 0;          ///< samples of each pixel per launch; 0: about 2^22 samples a launch
  std::int64_t pixels_per_launch = 0;  ///< pixels per launch; 0: all the call's pixels
  /// The simulation's cudaStream_t (null: none). Before reading any array Tessera waits for
  /// the work already queued on it (cudaStreamSynchronize); with none set it synchronises the
  /// whole device (cudaDeviceSynchronize). The call returns only when the GPU no longer reads
  /// the caller's arrays.
  void* stream = nullptr;
  /// Device bytes the call may hold (0: no limit): the scene's device copies (field copy,
  /// majorants, tables; counted whether made by this call or kept from an earlier one) plus
  /// the call's film sums, pixel list and counters. Counted before anything is allocated;
  /// over the limit throws std::runtime_error naming the bytes needed and the limit.
  std::uint64_t memory_limit_bytes = 0;
};

/// What a render_tiles_cuda call moved and where it ran.
struct CudaTransfer {
  std::string device_name;  ///< cudaDeviceProp::name
  std::uint64_t bytes_to_device =
      0;  ///< host -> device: field copy and tables (0 when kept from an earlier call), film sums
  std::uint64_t bytes_to_host = 0;  ///< device -> host: film sums, counters
  std::uint64_t device_bytes = 0;   ///< peak device bytes the call held (as memory_limit_bytes counts them)
  bool field_in_place = false;      ///< the field was device (or managed) memory, read in place
  bool scene_reused = false;        ///< the scene's device copies were kept from an earlier call
  int launches = 0;                 ///< kernel launches
  /// A distributed (paged) field: launches run again because a lookup found a brick not yet
  /// on the device (docs/gpu.md), and the bricks copied to the device (counted in
  /// bytes_to_device too)
  int replays = 0;
  std::uint64_t bricks = 0;
};

/// Where a pointer's memory lives, as the CUDA runtime says (cudaPointerGetAttributes).
enum class MemoryKind { Host, Device, Managed };

/// True when this build holds the CUDA backend.
bool cuda_built();

/// CUDA devices visible to this process; 0 when none, with *why (if given) saying why not:
/// built without CUDA, no driver, no device, the runtime's error, or the GPU disabled for the
/// process (cuda_disabled).
int cuda_device_count(std::string* why = nullptr);

/// Host for host memory (pageable or pinned), for a pointer the runtime does not know and in
/// a build without CUDA; Device or Managed for device and managed allocations. Leaves no error
/// behind in the runtime. Throws tessera::cuda::CudaError once the GPU is disabled (a device
/// pointer must then not be mistaken for host memory).
MemoryKind cuda_memory_kind(const void* p);

/// True once a CUDA call of the backend has returned a sticky error (an illegal address, a
/// launch failure, an uncorrectable ECC error, ...: the CUDA context is unusable for the rest
/// of the process); *why then names the error and the call. From then on every call of this
/// header that would touch the GPU throws tessera::cuda::CudaError saying that the GPU was
/// disabled for the process by that error. Thread-safe. False in a build without CUDA.
bool cuda_disabled(std::string* why = nullptr);

/// render_tiles on a GPU: adds spp samples to each pixel of the listed tiles, continuing each
/// pixel's sample indices, with counters in `stats` as the CPU counts them. Throws
/// std::invalid_argument for what the backend does not cover (named) or a bad film/tile index,
/// std::runtime_error naming the bytes for a call over launch.memory_limit_bytes or over the
/// device's free memory (checked before allocating), tessera::cuda::CudaError (a
/// std::runtime_error naming the CUDA call or kernel) for a CUDA failure, DeadlineExceeded
/// past options.deadline (the film then holds a partial image, as on the CPU). The call's own
/// device memory is released before it returns or throws; the scene's device copies stay with
/// the prepared scene (see above). Calls on one prepared scene may come from several threads.
void render_tiles_cuda(const PreparedScene& scene, std::span<const int> tile_indices, Film& film, RenderStats& stats,
                       const CudaLaunch& launch = {}, CudaTransfer* transfer = nullptr);

/// The FieldSummary of `field` (what FieldSummary::build(field, edge) gives, bit for bit) for
/// a field in device or managed memory, computed on the device that holds it by a reduction
/// over its macrocells (any byte strides, negative ones included), after the work queued on
/// `stream` (a cudaStream_t; null: the whole device is synchronised first). Pass it to
/// prepare(field, scene, summary) so that prepare reads no value of a device field. A host
/// field is summarised on the host (FieldSummary::build). Throws std::invalid_argument for an
/// invalid field or edge < 1, CudaError for a CUDA failure, std::runtime_error in a build
/// without CUDA for a pointer that is not host memory.
std::shared_ptr<const FieldSummary> cuda_field_summary(const FieldView& field, int edge, void* stream = nullptr);

/// FieldSummary::accumulate (field_summary.h) for a block that may be in device or managed
/// memory: the block's vertices folded into `parts` (the global field's macrocells), bit for
/// bit what accumulate gives, computed on the device that holds the block over the window of
/// macrocells it touches (only that window comes back to the host), after the work queued on
/// `stream`. A host block is accumulated on the host. Throws as accumulate does for parts,
/// block or offset that do not fit, and as cuda_field_summary does otherwise.
void cuda_field_summary_accumulate(FieldSummary::Parts& parts, const FieldView& block, const std::int64_t offset[3],
                                   const std::int64_t global_dims[3], int edge, void* stream = nullptr);

/// check_mesh_indices (mesh.h) for a mesh whose arrays are GPU memory (Mesh::device): the
/// descriptors on the host, then every real cell's indices and vertices on the device that
/// holds them, after the work queued on `stream`; throws check_mesh_indices'
/// std::invalid_argument, its words, for the first faulty cell. CUDA failures as
/// cuda_field_summary. Its receipt (MeshChecked) also carries the values' totals, measured on
/// the device in the same call (MeshChecked::values: the range a `range: auto` needs, and
/// what cuda_mesh_summary and prepare() then need not read again).
MeshChecked cuda_check_mesh_indices(const Mesh& mesh, void* stream = nullptr);

/// The macrocell summary of a mesh whose arrays are GPU memory (Mesh::device) over the uniform
/// grid at `grid` (origin, spacing) with `dims` vertices per axis that the layout of the same
/// geometry lays over it, for macrocell edge `edge` (>= 1): what prepare() computes on the
/// host for a host mesh, bit for bit, computed on the device that holds the arrays after the
/// work queued on `stream`. For a mesh check_mesh_indices accepts. `checked`: a receipt of
/// cuda_check_mesh_indices that covers `mesh`, whose value totals are used instead of reading
/// the values again (null, or one that does not cover it: they are read). Throws as
/// cuda_field_summary does.
std::shared_ptr<const FieldSummary> cuda_mesh_summary(const Mesh& mesh, const VolumeGeometry& grid,
                                                      const std::int64_t dims[3], int edge, void* stream = nullptr,
                                                      const MeshChecked* checked = nullptr);

/// mesh_geometry_hash (mesh.h) of a mesh whose arrays are GPU memory (Mesh::device): the
/// descriptors checked on the host (check_mesh_descriptors), the items summed on the device
/// that holds them after the work queued on `stream`; the same value as the host's for the
/// same geometry. Throws as cuda_field_summary does.
MeshGeometryHash cuda_mesh_geometry_hash(const Mesh& mesh, void* stream = nullptr);

/// The item sums of a GPU mesh's ghost masks alone (the geometry hash's items, not finished
/// with the descriptors; {0, 0} without masks), on the device after the work queued on
/// `stream`: what prepare() compares with the masks a reused layout was built over, so that no
/// cell of the layout is a ghost now (ghosts' indices are never checked). Throws as
/// cuda_mesh_geometry_hash does.
MeshGeometryHash cuda_mesh_ghost_sums(const Mesh& mesh, void* stream = nullptr);

/// The finite min / max of the values of a mesh whose arrays are GPU memory (Mesh::device),
/// ghost cells' values left out for cell data (+Inf, -Inf when none), computed on the device
/// that holds them after the work queued on `stream`. Throws as cuda_field_summary does.
std::pair<double, double> cuda_mesh_value_range(const Mesh& mesh, void* stream = nullptr);

}  // namespace tessera
