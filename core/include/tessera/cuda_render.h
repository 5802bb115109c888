#pragma once
/// The CUDA backend's entry (docs/gpu.md): renders a prepared scene's tiles on a GPU with the
/// CPU's per-sample code (the kernel headers compile for both, host_device.h): the same
/// random streams as a function of (seed, frame, pixel, sample index), the same estimator,
/// each pixel's samples added in index order. Images agree with the CPU's within Monte Carlo
/// error (floating-point rounding and the device's math library differ), and on one GPU model
/// the bits are the same on every run and for any CudaLaunch.
///
/// Declared in every build: where Tessera was built without CUDA (TESSERA_CUDA=OFF, or no
/// nvcc found) cuda_built() is false, cuda_device_count() is 0 and render_tiles_cuda throws.
///
/// Covered so far (issue 42, the groundwork): uniform float32 and float64 fields (host
/// memory, copied for the call, or device memory, read in place), uniform sampling, every
/// light kind, constant and gradient backgrounds, every integrator mode, denoiser features.
/// Refused by name (std::invalid_argument): other dtypes, rectilinear axes, refinement
/// levels, meshes, paged and vector-magnitude fields, adaptive sampling, envmap backgrounds.
#include <tessera/film.h>
#include <tessera/render.h>
#include <tessera/stats.h>

#include <cstdint>
#include <span>
#include <string>

namespace tessera {

/// How render_tiles_cuda cuts its work into kernel launches. Launches are bounded slices
/// (some samples of some pixels each); the deadline (options.deadline) is checked between
/// them. The image does not depend on any of these numbers.
struct CudaLaunch {
  int device = 0;                      ///< CUDA device index (cudaSetDevice)
  int block_threads = 128;             ///< threads per block: one pixel each
  int samples_per_launch = 0;          ///< samples of each pixel per launch; 0: about 2^22 samples a launch
  std::int64_t pixels_per_launch = 0;  ///< pixels per launch; 0: all the call's pixels
};

/// What a render_tiles_cuda call moved and where it ran.
struct CudaTransfer {
  std::string device_name;            ///< cudaDeviceProp::name
  std::uint64_t bytes_to_device = 0;  ///< host -> device: field copy (if any), tables, film sums
  std::uint64_t bytes_to_host = 0;    ///< device -> host: film sums, counters
  bool field_in_place = false;        ///< the field was device (or managed) memory, read in place
  int launches = 0;                   ///< kernel launches
};

/// True when this build holds the CUDA backend.
bool cuda_built();

/// CUDA devices visible to this process; 0 when none, with *why (if given) saying why not:
/// built without CUDA, no driver, no device, or the runtime's error.
int cuda_device_count(std::string* why = nullptr);

/// render_tiles on a GPU: adds spp samples to each pixel of the listed tiles, continuing each
/// pixel's sample indices, with counters in `stats` as the CPU counts them. Throws
/// std::invalid_argument for what the backend does not cover (named) or a bad film/tile index,
/// tessera::cuda::CudaError (a std::runtime_error naming the CUDA call) for a CUDA failure,
/// DeadlineExceeded past options.deadline (the film then holds a partial image, as on the
/// CPU). Device memory is released before it returns or throws.
void render_tiles_cuda(const PreparedScene& scene, std::span<const int> tile_indices, Film& film, RenderStats& stats,
                       const CudaLaunch& launch = {}, CudaTransfer* transfer = nullptr);

}  // namespace tessera
