/// render_tiles_cuda (cuda_render.h), the host half of the CUDA backend: checks what the
/// device kernels cover, waits for the simulation's stream, finds or makes the prepared
/// scene's device copies (device_scene.h) within the memory limit and the device's free
/// memory, copies the tiles' pixel sums to the device, launches bounded slices
/// (pixel_kernel.h) with the deadline checked between them, and copies the sums and counters
/// back. Every CUDA call goes through cuda_check; cuda_memory_kind and cuda_device_count too.
#include <tessera/cuda_render.h>

#include "cuda/cuda_check.h"
#include "cuda/device_scene.h"
#include "cuda/pixel_kernel.h"
#include "kernel/stop_check.h"
#include "scene/prepared_scene_impl.h"

#include <cuda_runtime_api.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera {

using cuda::cuda_check;
using cuda::DeviceBuffer;
using cuda::DeviceScene;

bool cuda_built() { return true; }

int cuda_device_count(std::string* why) {
  if (std::string disabled; cuda_disabled(&disabled)) {
    if (why) *why = "the GPU was disabled for the process by " + disabled;
    return 0;
  }
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

MemoryKind cuda_memory_kind(const void* p) {
  cuda::throw_if_disabled();
  if (p == nullptr) return MemoryKind::Host;
  cudaPointerAttributes attr{};
  const cudaError_t e = cudaPointerGetAttributes(&attr, p);
  if (e != cudaSuccess) {
    if (cuda::is_sticky(e)) cuda_check(e, "cudaPointerGetAttributes");
    cudaGetLastError();  // no driver, no device, or an old runtime's unregistered pointer: not sticky
    return MemoryKind::Host;
  }
  switch (attr.type) {
    case cudaMemoryTypeDevice: return MemoryKind::Device;
    case cudaMemoryTypeManaged: return MemoryKind::Managed;
    default: return MemoryKind::Host;  // unregistered or pinned host memory
  }
}

namespace {

/// Samples a launch holds at most by default (CudaLaunch::samples_per_launch 0): a few
/// milliseconds to a second of work on one GPU, so the deadline is seen often enough.
constexpr std::int64_t kDefaultSamplesPerLaunch = std::int64_t{1} << 22;

/// Guards every PreparedSceneImpl::device_cache (looked up and filled under it).
std::mutex g_cache_mutex;

/// What the kernels read that the device does not cover yet: empty when covered.
std::string unsupported(const PreparedSceneImpl& s) {
  std::string why;
  if (!cuda::device_value_supported(s.kernel, &why)) return why;
  if (s.kernel.target_error > 0.0) return "adaptive sampling (image.target_error)";
  if (s.desc.background.type == BackgroundType::EnvMap) return "an envmap background";
  return {};
}

std::string mib(std::uint64_t bytes) {
  return std::to_string(bytes) + " bytes (" + std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB)";
}

}  // namespace

void render_tiles_cuda(const PreparedScene& scene, std::span<const int> tile_indices, Film& film, RenderStats& stats,
                       const CudaLaunch& launch, CudaTransfer* transfer) {
  cuda::throw_if_disabled();
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

  // The simulation's queued work first: nothing is read before it is done
  if (launch.stream)
    cuda_check(cudaStreamSynchronize(static_cast<cudaStream_t>(launch.stream)),
               "cudaStreamSynchronize(the simulation's stream, before reading its arrays)");
  else cuda_check(cudaDeviceSynchronize(), "cudaDeviceSynchronize (before reading the field)");

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
  std::array<unsigned long long, cuda::kCounterCount> counters{};
  // Each pixel's samples in `lanes` threads (pixel_kernel.h): their sums on the device only
  const int spp = s.kernel.spp;
  const int lanes = cuda::sample_lanes(s.desc.image.width, s.desc.image.height, spp);
  const std::uint64_t lane_bytes =
      static_cast<std::uint64_t>(jobs.size()) * lanes * (sizeof(PixelSums) + (aux.empty() ? 0 : sizeof(AuxSums)));
  const std::uint64_t call_bytes = jobs.size() * sizeof(cuda::PixelJob) + px.size() * sizeof(PixelSums) +
                                   aux.size() * sizeof(AuxSums) + sizeof(counters) + lane_bytes;

  // The scene's device copies: kept from an earlier call on this device, or made now. The
  // bytes are counted against the limit and the device's free memory before any allocation.
  std::uint64_t to_device = 0, device_bytes = 0;
  std::shared_ptr<DeviceScene> dev;
  bool reused = false;
  {
    const std::lock_guard lock(g_cache_mutex);
    auto cached = std::static_pointer_cast<DeviceScene>(s.device_cache);
    reused = cached && cached->device() == launch.device;
    dev = reused ? std::move(cached) : std::make_shared<DeviceScene>(s, launch.device);
    device_bytes = dev->bytes() + call_bytes;
    const std::uint64_t new_bytes = (reused ? 0 : dev->bytes()) + call_bytes;
    if (launch.memory_limit_bytes > 0 && device_bytes > launch.memory_limit_bytes)
      throw std::runtime_error("render_tiles_cuda: needs " + mib(device_bytes) + " of device memory (scene copies " +
                               mib(dev->bytes()) + ", this call's pixels " + mib(call_bytes) +
                               "), over the memory limit of " + mib(launch.memory_limit_bytes));
    std::size_t free_bytes = 0, total_bytes = 0;
    cuda_check(cudaMemGetInfo(&free_bytes, &total_bytes), "cudaMemGetInfo");
    if (new_bytes > free_bytes)
      throw std::runtime_error("render_tiles_cuda: needs " + mib(new_bytes) + " of device memory (scene copies " +
                               mib(reused ? 0 : dev->bytes()) + ", this call's pixels " + mib(call_bytes) + "), but " +
                               prop.name + " has " + mib(free_bytes) + " free of " + mib(total_bytes));
    if (!reused) {
      to_device += dev->upload();
      s.device_cache = dev;  // the prepared scene keeps them; freed with it
    }
  }

  DeviceBuffer d_jobs, d_px, d_aux, d_counters;
  to_device += d_jobs.upload(jobs.data(), jobs.size() * sizeof(cuda::PixelJob), "pixel list");
  to_device += d_px.upload(px.data(), px.size() * sizeof(PixelSums), "pixel sums");
  if (!aux.empty()) to_device += d_aux.upload(aux.data(), aux.size() * sizeof(AuxSums), "auxiliary sums");
  to_device += d_counters.upload(counters.data(), sizeof(counters), "counters");
  DeviceBuffer d_lane_px, d_lane_aux;
  d_lane_px.allocate(jobs.size() * lanes * sizeof(PixelSums), "sample lanes' sums");
  cuda_check(cudaMemset(d_lane_px.get(), 0, d_lane_px.bytes()), "cudaMemset(sample lanes' sums)");
  if (!aux.empty()) {
    d_lane_aux.allocate(jobs.size() * lanes * sizeof(AuxSums), "sample lanes' auxiliary sums");
    cuda_check(cudaMemset(d_lane_aux.get(), 0, d_lane_aux.bytes()), "cudaMemset(sample lanes' auxiliary sums)");
  }

  // Bounded slices: all pixels' next few samples at a time; each lane's samples are drawn
  // and added in index order whatever the slicing
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
      cuda::SliceArgs a{dev->kernel(),
                        dev->medium(),
                        d_jobs.as<cuda::PixelJob>(),
                        d_px.as<PixelSums>(),
                        d_lane_px.as<PixelSums>(),
                        aux.empty() ? nullptr : d_lane_aux.as<AuxSums>(),
                        d_counters.as<unsigned long long>(),
                        j0,
                        std::min(njobs, j0 + per_launch_px),
                        s0,
                        std::min(spp, s0 + per_launch_spp),
                        lanes};
      cuda::launch_pixel_slice(dev->dispatch_scene(), a, launch.block_threads);
      ++launches;
      cuda_check(cudaDeviceSynchronize(), cuda::pixel_kernel_name(s.kernel) + " slice (samples " + std::to_string(s0) +
                                              "+, pixels " + std::to_string(j0) + "+ of " + std::to_string(njobs) +
                                              ")");
    }
  }

  // The lanes into the pixels (also after a deadline: the film holds the samples drawn), then
  // the sums back into the film, the counters into the stats
  cuda::merge_lanes(d_px.as<PixelSums>(), aux.empty() ? nullptr : d_aux.as<AuxSums>(), d_lane_px.as<PixelSums>(),
                    aux.empty() ? nullptr : d_lane_aux.as<AuxSums>(), njobs, lanes);
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
    transfer->device_bytes = device_bytes;
    transfer->field_in_place = dev->field_in_place();
    transfer->scene_reused = reused;
    transfer->launches = launches;
  }
  if (stopped) throw DeadlineExceeded(0, tile_indices.size());
}

}  // namespace tessera
