/// render_tiles_cuda (cuda_render.h), the host half of the CUDA backend: checks what the
/// device kernels cover, copies what the KernelScene points to (field, majorants, empty-space
/// reach, transfer function, lights, background) and the tiles' pixel sums to the device,
/// launches bounded slices (pixel_kernel.cu) with the deadline checked between them, and
/// copies the sums and counters back. Every CUDA call goes through cuda_check.
#include <tessera/cuda_render.h>

#include "cuda/cuda_check.h"
#include "cuda/pixel_kernel.h"
#include "kernel/stop_check.h"
#include "scene/prepared_scene_impl.h"

#include <cuda_runtime_api.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera {

using cuda::cuda_check;
using cuda::DeviceBuffer;

bool cuda_built() { return true; }

int cuda_device_count(std::string* why) {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) {
    if (why) *why = std::string("no CUDA device: ") + cudaGetErrorName(e) + " (" + cudaGetErrorString(e) + ")";
    cudaGetLastError();  // not sticky: clear it
    return 0;
  }
  if (n == 0 && why) *why = "no CUDA device is visible";
  return n;
}

namespace {

/// Samples a launch holds at most by default (CudaLaunch::samples_per_launch 0): a few
/// milliseconds to a second of work on one GPU, so the deadline is seen often enough.
constexpr std::int64_t kDefaultSamplesPerLaunch = std::int64_t{1} << 22;

/// The first byte and the byte past the last element of a strided view, as offsets from
/// its data pointer (negative strides reach below it).
void field_span(const FieldView& f, std::int64_t* lo, std::int64_t* hi) {
  *lo = 0;
  *hi = static_cast<std::int64_t>(dtype_size(f.dtype));
  for (int a = 0; a < 3; ++a) {
    const std::int64_t reach = (f.dims[a] - 1) * f.byte_strides[a];
    if (reach < 0) *lo += reach;
    else *hi += reach;
  }
}

/// What the kernels read that the device does not cover yet: empty when covered.
std::string unsupported(const PreparedSceneImpl& s) {
  std::string why;
  if (!cuda::device_value_supported(s.kernel, &why)) return why;
  if (s.kernel.target_error > 0.0) return "adaptive sampling (image.target_error)";
  if (s.desc.background.type == BackgroundType::EnvMap) return "an envmap background";
  return {};
}

/// The scene's device copies: every table the KernelScene points to, and the KernelScene
/// and medium over them.
struct DeviceScene {
  DeviceBuffer field, majorant, empty_reach, tf, env, lights, kernel, medium;
  std::uint64_t bytes = 0;  ///< copied to the device
  bool field_in_place = false;

  explicit DeviceScene(const PreparedSceneImpl& s) {
    const KernelScene& ks = s.kernel;
    KernelScene d = ks;
    // The field: device or managed memory is read in place, host memory copied
    cudaPointerAttributes attr{};
    const cudaError_t pe = cudaPointerGetAttributes(&attr, ks.field.data);
    if (pe != cudaSuccess) cudaGetLastError();  // an unregistered host pointer on old runtimes: not sticky
    field_in_place = pe == cudaSuccess && (attr.type == cudaMemoryTypeDevice || attr.type == cudaMemoryTypeManaged);
    if (!field_in_place) {
      std::int64_t lo, hi;
      field_span(ks.field, &lo, &hi);
      const auto* base = static_cast<const unsigned char*>(ks.field.data);
      bytes += field.upload(base + lo, static_cast<std::size_t>(hi - lo), "field copy");
      d.field.data = field.as<unsigned char>() - lo;
    }
    // Majorants and empty-space reach, one per macrocell
    const auto cells = static_cast<std::size_t>(ks.cells[0] * ks.cells[1] * ks.cells[2]);
    bytes += majorant.upload(ks.majorant, cells * sizeof(double), "majorants");
    d.majorant = majorant.as<double>();
    if (ks.empty_reach) {
      bytes += empty_reach.upload(ks.empty_reach, cells, "empty-space reach");
      d.empty_reach = empty_reach.as<std::uint8_t>();
    }
    bytes += tf.upload(ks.tf, sizeof(TransferFunction), "transfer function");
    d.tf = tf.as<TransferFunction>();
    // The background (constant or gradient: no tables) and the lights, the background light
    // pointing at the device's copy
    bytes += env.upload(&s.env, sizeof(Environment), "background");
    const auto* env_dev = env.as<Environment>();
    std::vector<Light> host_lights;
    for (int i = 0; i < ks.lights.count(); ++i)
      host_lights.push_back(i < ks.lights.area_count() ? ks.lights[i] : Light(EnvironmentLight(env_dev)));
    bytes += lights.upload(host_lights.data(), host_lights.size() * sizeof(Light), "lights");
    d.lights = ks.lights.relocated(lights.as<Light>(), env_dev);
    // No tile list on the device: the host hands it pixels
    d.tiles = nullptr;
    d.tile_culled = nullptr;
    d.tile_count = 0;
    bytes += kernel.upload(&d, sizeof(KernelScene), "kernel scene");
    std::vector<unsigned char> m(cuda::device_medium_bytes(d));
    cuda::make_device_medium(d, m.data());
    bytes += medium.upload(m.data(), m.size(), "medium");
  }
};

}  // namespace

void render_tiles_cuda(const PreparedScene& scene, std::span<const int> tile_indices, Film& film, RenderStats& stats,
                       const CudaLaunch& launch, CudaTransfer* transfer) {
  const PreparedSceneImpl& s = prepared_scene_impl(scene);
  if (film.width() != s.desc.image.width || film.height() != s.desc.image.height)
    throw std::invalid_argument("film is " + std::to_string(film.width()) + "x" + std::to_string(film.height()) +
                                ", scene image is " + std::to_string(s.desc.image.width) + "x" +
                                std::to_string(s.desc.image.height));
  const int ntiles = static_cast<int>(s.tiles.size());
  for (int i : tile_indices)
    if (i < 0 || i >= ntiles) throw std::out_of_range("tile index " + std::to_string(i) + " out of range");
  if (const std::string why = unsupported(s); !why.empty())
    throw std::invalid_argument("render_tiles_cuda: " + why + " is not supported on the GPU yet; render it on the CPU");
  std::string why;
  const int ndev = cuda_device_count(&why);
  if (ndev == 0) throw std::runtime_error("render_tiles_cuda: " + why);
  if (launch.device < 0 || launch.device >= ndev)
    throw std::invalid_argument("render_tiles_cuda: device " + std::to_string(launch.device) + " of " +
                                std::to_string(ndev) + " visible");
  cuda_check(cudaSetDevice(launch.device), "cudaSetDevice(" + std::to_string(launch.device) + ")");
  cudaDeviceProp prop{};
  cuda_check(cudaGetDeviceProperties(&prop, launch.device), "cudaGetDeviceProperties");
  const auto t_start = std::chrono::steady_clock::now();

  // The pixels of the listed tiles, in tile order, and their sums so far
  std::vector<cuda::PixelJob> jobs;
  for (const int i : tile_indices) {
    const Tile& t = s.tiles[static_cast<std::size_t>(i)];
    for (int y = t.y0; y < t.y1; ++y)
      for (int x = t.x0; x < t.x1; ++x) jobs.push_back({x, y, s.tile_culled[static_cast<std::size_t>(i)] != 0});
  }
  const auto njobs = static_cast<std::int64_t>(jobs.size());
  std::vector<PixelSums> px(jobs.size());
  std::vector<AuxSums> aux(film.has_aux() ? jobs.size() : 0);
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    px[j] = film.at(jobs[j].x, jobs[j].y);
    if (film.has_aux()) aux[j] = *film.aux_at(jobs[j].x, jobs[j].y);
  }

  DeviceScene dev(s);
  std::uint64_t to_device = dev.bytes;
  DeviceBuffer d_jobs, d_px, d_aux, d_counters;
  to_device += d_jobs.upload(jobs.data(), jobs.size() * sizeof(cuda::PixelJob), "pixel list");
  to_device += d_px.upload(px.data(), px.size() * sizeof(PixelSums), "pixel sums");
  if (!aux.empty()) to_device += d_aux.upload(aux.data(), aux.size() * sizeof(AuxSums), "auxiliary sums");
  std::array<unsigned long long, cuda::kCounterCount> counters{};
  to_device += d_counters.upload(counters.data(), sizeof(counters), "counters");

  // Bounded slices: all pixels' next few samples at a time, so every pixel's samples are
  // drawn and added in index order whatever the slicing
  const int spp = s.kernel.spp;
  const std::int64_t per_launch_px =
      launch.pixels_per_launch > 0 ? launch.pixels_per_launch : std::max<std::int64_t>(njobs, 1);
  const int per_launch_spp = launch.samples_per_launch > 0
                                 ? launch.samples_per_launch
                                 : static_cast<int>(std::clamp<std::int64_t>(
                                       kDefaultSamplesPerLaunch / std::max<std::int64_t>(njobs, 1), 1, spp));
  StopCheck stop(s.desc.options.deadline);
  int launches = 0;
  bool stopped = false;
  for (int s0 = 0; s0 < spp && !stopped; s0 += per_launch_spp) {
    for (std::int64_t j0 = 0; j0 < njobs; j0 += per_launch_px) {
      if (stop.stop()) {
        stopped = true;
        break;
      }
      cuda::SliceArgs a{dev.kernel.as<KernelScene>(),
                        dev.medium.get(),
                        d_jobs.as<cuda::PixelJob>(),
                        d_px.as<PixelSums>(),
                        d_aux.as<AuxSums>(),
                        d_counters.as<unsigned long long>(),
                        j0,
                        std::min(njobs, j0 + per_launch_px),
                        std::min(per_launch_spp, spp - s0)};
      cuda::launch_pixel_slice(s.kernel, a, launch.block_threads);
      ++launches;
      cuda_check(cudaDeviceSynchronize(), "pixel_samples slice (samples " + std::to_string(s0) + "+, pixels " +
                                              std::to_string(j0) + "+ of " + std::to_string(njobs) + ")");
    }
  }

  // The sums back into the film, the counters into the stats
  std::uint64_t to_host = 0;
  cuda_check(cudaMemcpy(px.data(), d_px.get(), px.size() * sizeof(PixelSums), cudaMemcpyDeviceToHost),
             "cudaMemcpy(pixel sums to the host)");
  to_host += px.size() * sizeof(PixelSums);
  if (!aux.empty()) {
    cuda_check(cudaMemcpy(aux.data(), d_aux.get(), aux.size() * sizeof(AuxSums), cudaMemcpyDeviceToHost),
               "cudaMemcpy(auxiliary sums to the host)");
    to_host += aux.size() * sizeof(AuxSums);
  }
  cuda_check(cudaMemcpy(counters.data(), d_counters.get(), sizeof(counters), cudaMemcpyDeviceToHost),
             "cudaMemcpy(counters to the host)");
  to_host += sizeof(counters);
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    film.at(jobs[j].x, jobs[j].y) = px[j];
    if (!aux.empty()) *film.aux_at(jobs[j].x, jobs[j].y) = aux[j];
  }
  stats.samples += counters[cuda::kSamples];
  stats.free_flight_lookups += counters[cuda::kFreeFlightLookups];
  stats.transmittance_lookups += counters[cuda::kTransmittanceLookups];
  stats.gradient_lookups += counters[cuda::kGradientLookups];
  stats.real_collisions += counters[cuda::kRealCollisions];
  stats.null_collisions += counters[cuda::kNullCollisions];
  stats.discarded_samples += counters[cuda::kDiscardedSamples];
  stats.stalled_paths += counters[cuda::kStalledPaths];
  for (const int i : tile_indices) stats.tiles_skipped += s.tile_culled[static_cast<std::size_t>(i)] != 0;
  stats.tiles_total += tile_indices.size();
  stats.nan_voxels_seen = s.grid.nan_vertices();
  stats.threads = 1;
  stats.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (transfer) {
    transfer->device_name = prop.name;
    transfer->bytes_to_device = to_device;
    transfer->bytes_to_host = to_host;
    transfer->field_in_place = dev.field_in_place;
    transfer->launches = launches;
  }
  if (stopped) throw DeadlineExceeded(0, tile_indices.size());
}

}  // namespace tessera
