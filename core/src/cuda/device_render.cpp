/// render_on_device (device_render.h).
#include "cuda/device_render.h"

#include <tessera/memory_estimate.h>

#include "cuda/device_scene.h"
#include "cuda/pixel_kernel.h"
#include "kernel/stop_check.h"
#include "render/tiles_call.h"
#include "scene/prepared_scene_impl.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::cuda {

namespace {

/// Samples a launch holds at most by default (CudaLaunch::samples_per_launch 0): a few
/// milliseconds to a second of work on one GPU, so the deadline is seen often enough.
constexpr std::int64_t kDefaultSamplesPerLaunch = std::int64_t{1} << 22;

/// Guards every PreparedSceneImpl::device_cache (looked up and filled under it).
std::mutex g_cache_mutex;

/// What the kernels read that the device does not cover yet: empty when covered.
std::string unsupported(const DeviceBackend& b, const PreparedSceneImpl& s) {
  std::string why;
  if (!b.covers(s.kernel, &why)) return why;
  if (s.kernel.target_error > 0.0) return "adaptive sampling (image.target_error)";
  return {};
}

std::string mib(std::uint64_t bytes) {
  return std::to_string(bytes) + " bytes (" + std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB)";
}

// The host copies of a call as the memory estimate counts them (memory_estimate.h)
static_assert(sizeof(PixelJob) + sizeof(PixelSums) == kGpuHostBytesPerPixel);

/// The pixels of the listed tiles, in tile order.
std::vector<PixelJob> pixel_jobs(const PreparedSceneImpl& s, std::span<const int> tile_indices) {
  std::vector<PixelJob> jobs;
  for (const int i : tile_indices) {
    const Tile& t = s.tiles[static_cast<std::size_t>(i)];
    for (int y = t.y0; y < t.y1; ++y)
      for (int x = t.x0; x < t.x1; ++x) jobs.push_back({x, y, s.tile_culled[static_cast<std::size_t>(i)] != 0});
  }
  return jobs;
}

/// The scene's device copies on `backend`: kept from an earlier call on it, or made now, the
/// bytes counted against the limit and the device's free memory before any allocation.
std::shared_ptr<DeviceScene> device_scene(const std::shared_ptr<DeviceBackend>& backend, const PreparedSceneImpl& s,
                                          const CudaLaunch& launch, std::uint64_t call_bytes, std::uint64_t* to_device,
                                          std::uint64_t* device_bytes, bool* reused) {
  const std::lock_guard lock(g_cache_mutex);
  auto dev = std::static_pointer_cast<DeviceScene>(s.device_cache);
  *reused = dev && dev->backend() == backend.get();
  if (!*reused) dev = std::make_shared<DeviceScene>(s, backend);
  *device_bytes = dev->bytes() + call_bytes;
  const std::uint64_t new_bytes = (*reused ? 0 : dev->bytes()) + call_bytes;
  if (launch.memory_limit_bytes > 0 && *device_bytes > launch.memory_limit_bytes)
    throw std::runtime_error("render_tiles_cuda: needs " + mib(*device_bytes) + " of device memory (scene copies " +
                             mib(dev->bytes()) + ", this call's pixels " + mib(call_bytes) +
                             "), over the memory limit of " + mib(launch.memory_limit_bytes));
  std::size_t free_bytes = 0, total_bytes = 0;
  backend->memory_info(&free_bytes, &total_bytes);
  if (new_bytes > free_bytes)
    throw std::runtime_error("render_tiles_cuda: needs " + mib(new_bytes) + " of device memory (scene copies " +
                             mib(*reused ? 0 : dev->bytes()) + ", this call's pixels " + mib(call_bytes) + "), but " +
                             backend->name() + " has " + mib(free_bytes) + " free of " + mib(total_bytes));
  if (!*reused) {
    *to_device += dev->upload();
    s.device_cache = dev;  // the prepared scene keeps them; freed with it
  }
  return dev;
}

}  // namespace

void render_on_device(const std::shared_ptr<DeviceBackend>& backend, const PreparedScene& scene,
                      std::span<const int> tile_indices, Film& film, RenderStats& stats, const CudaLaunch& launch,
                      CudaTransfer* transfer) {
  DeviceBackend& b = *backend;
  const PreparedSceneImpl& s = prepared_scene_impl(scene);
  check_tiles_call(s, film, tile_indices);
  if (const std::string why = unsupported(b, s); !why.empty())
    throw std::invalid_argument("render_tiles_cuda: " + why + " is not supported on the GPU yet; render it on the CPU");
  const auto t_start = std::chrono::steady_clock::now();

  // The simulation's queued work first: nothing is read before it is done
  b.wait_for_caller(launch.stream);

  // The pixels of the listed tiles and their sums so far
  const std::vector<PixelJob> jobs = pixel_jobs(s, tile_indices);
  const auto njobs = static_cast<std::int64_t>(jobs.size());
  std::vector<PixelSums> px(jobs.size());
  std::vector<AuxSums> aux(film.has_aux() ? jobs.size() : 0);
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    px[j] = film.at(jobs[j].x, jobs[j].y);
    if (film.has_aux()) aux[j] = *film.aux_at(jobs[j].x, jobs[j].y);
  }
  std::array<unsigned long long, kCounterCount> counters{};
  // Each pixel's samples in `lanes` threads (pixel_kernel.h): their sums on the device only
  const int spp = s.kernel.spp;
  const int lanes = sample_lanes(s.desc.image.width, s.desc.image.height, spp);
  const std::uint64_t lane_bytes =
      static_cast<std::uint64_t>(jobs.size()) * lanes * (sizeof(PixelSums) + (aux.empty() ? 0 : sizeof(AuxSums)));
  const std::uint64_t call_bytes = jobs.size() * sizeof(PixelJob) + px.size() * sizeof(PixelSums) +
                                   aux.size() * sizeof(AuxSums) + sizeof(counters) + lane_bytes;

  std::uint64_t to_device = 0, device_bytes = 0;
  bool reused = false;
  const std::shared_ptr<DeviceScene> dev =
      device_scene(backend, s, launch, call_bytes, &to_device, &device_bytes, &reused);

  BackendBuffer d_jobs(b), d_px(b), d_aux(b), d_counters(b), d_lane_px(b), d_lane_aux(b);
  to_device += d_jobs.upload(jobs.data(), jobs.size() * sizeof(PixelJob), "pixel list");
  to_device += d_px.upload(px.data(), px.size() * sizeof(PixelSums), "pixel sums");
  if (!aux.empty()) to_device += d_aux.upload(aux.data(), aux.size() * sizeof(AuxSums), "auxiliary sums");
  to_device += d_counters.upload(counters.data(), sizeof(counters), "counters");
  d_lane_px.allocate(jobs.size() * lanes * sizeof(PixelSums), "sample lanes' sums");
  b.zero(d_lane_px.get(), d_lane_px.bytes(), "sample lanes' sums");
  if (!aux.empty()) {
    d_lane_aux.allocate(jobs.size() * lanes * sizeof(AuxSums), "sample lanes' auxiliary sums");
    b.zero(d_lane_aux.get(), d_lane_aux.bytes(), "sample lanes' auxiliary sums");
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
      const SliceArgs a{dev->kernel(),
                        dev->medium(),
                        d_jobs.as<PixelJob>(),
                        d_px.as<PixelSums>(),
                        d_lane_px.as<PixelSums>(),
                        aux.empty() ? nullptr : d_lane_aux.as<AuxSums>(),
                        d_counters.as<unsigned long long>(),
                        j0,
                        std::min(njobs, j0 + per_launch_px),
                        s0,
                        std::min(spp, s0 + per_launch_spp),
                        lanes};
      b.run_slice(dev->dispatch_scene(), a, launch.block_threads,
                  pixel_kernel_name(s.kernel) + " slice (samples " + std::to_string(s0) + "+, pixels " +
                      std::to_string(j0) + "+ of " + std::to_string(njobs) + ")");
      ++launches;
    }
  }

  // The lanes into the pixels (also after a deadline: the film holds the samples drawn), then
  // the sums back into the film, the counters into the stats
  b.merge_lanes(d_px.as<PixelSums>(), aux.empty() ? nullptr : d_aux.as<AuxSums>(), d_lane_px.as<PixelSums>(),
                aux.empty() ? nullptr : d_lane_aux.as<AuxSums>(), njobs, lanes);
  std::uint64_t to_host = 0;
  b.copy_to_host(px.data(), d_px.get(), px.size() * sizeof(PixelSums), "pixel sums");
  to_host += px.size() * sizeof(PixelSums);
  if (!aux.empty()) {
    b.copy_to_host(aux.data(), d_aux.get(), aux.size() * sizeof(AuxSums), "auxiliary sums");
    to_host += aux.size() * sizeof(AuxSums);
  }
  b.copy_to_host(counters.data(), d_counters.get(), sizeof(counters), "counters");
  to_host += sizeof(counters);
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    film.at(jobs[j].x, jobs[j].y) = px[j];
    if (!aux.empty()) *film.aux_at(jobs[j].x, jobs[j].y) = aux[j];
  }
  stats.samples += counters[kSamples];
  stats.free_flight_lookups += counters[kFreeFlightLookups];
  stats.transmittance_lookups += counters[kTransmittanceLookups];
  stats.gradient_lookups += counters[kGradientLookups];
  stats.real_collisions += counters[kRealCollisions];
  stats.null_collisions += counters[kNullCollisions];
  stats.discarded_samples += counters[kDiscardedSamples];
  stats.stalled_paths += counters[kStalledPaths];
  for (const int i : tile_indices) stats.tiles_skipped += s.tile_culled[static_cast<std::size_t>(i)] != 0;
  stats.tiles_total += tile_indices.size();
  stats.nan_voxels_seen = s.grid.nan_vertices();
  stats.threads = 1;
  stats.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (transfer) {
    transfer->device_name = b.name();
    transfer->bytes_to_device = to_device;
    transfer->bytes_to_host = to_host;
    transfer->device_bytes = device_bytes;
    transfer->field_in_place = dev->field_in_place();
    transfer->scene_reused = reused;
    transfer->launches = launches;
  }
  if (stopped) throw DeadlineExceeded(0, tile_indices.size());
}

}  // namespace tessera::cuda
