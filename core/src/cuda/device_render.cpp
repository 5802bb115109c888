/// render_on_device (device_render.h).
#include "cuda/device_render.h"

#include <tessera/memory_estimate.h>

#include "cuda/adaptive_plan.h"
#include "cuda/device_scene.h"
#include "cuda/pixel_kernel.h"
#include "cuda/replay_slice.h"
#include "kernel/adaptive_sampling.h"
#include "kernel/stop_check.h"
#include "kernels/lane_kernel.h"
#include "render/tiles_call.h"
#include "scene/prepared_scene_impl.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
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
  if (!*reused) {
    // A distributed field's brick pool takes what the limit and the device leave
    std::uint64_t budget = 0;
    if (s.kernel.paged.cache != nullptr) {
      std::size_t free_bytes = 0, total_bytes = 0;
      backend->memory_info(&free_bytes, &total_bytes);
      budget = free_bytes;
      if (launch.memory_limit_bytes > 0) budget = std::min<std::uint64_t>(budget, launch.memory_limit_bytes);
      budget = budget > call_bytes ? budget - call_bytes : 1;
    }
    dev = std::make_shared<DeviceScene>(s, backend, budget);
  }
  *device_bytes = dev->bytes() + call_bytes;
  const std::uint64_t new_bytes = (*reused ? 0 : dev->new_bytes()) + call_bytes;
  if (launch.memory_limit_bytes > 0 && *device_bytes > launch.memory_limit_bytes)
    throw std::runtime_error("render_tiles_cuda: needs " + mib(*device_bytes) + " of device memory (scene copies " +
                             mib(dev->bytes()) + ", this call's pixels " + mib(call_bytes) +
                             "), over the memory limit of " + mib(launch.memory_limit_bytes));
  std::size_t free_bytes = 0, total_bytes = 0;
  backend->memory_info(&free_bytes, &total_bytes);
  if (new_bytes > free_bytes)
    throw std::runtime_error("render_tiles_cuda: needs " + mib(new_bytes) + " of device memory (scene copies " +
                             mib(*reused ? 0 : dev->new_bytes()) + ", this call's pixels " + mib(call_bytes) +
                             "), but " + backend->name() + " has " + mib(free_bytes) + " free of " + mib(total_bytes));
  if (!*reused) {
    *to_device += dev->upload();
    s.device_cache = dev;  // the prepared scene keeps them; freed with it
  }
  return dev;
}

/// A call's running totals over its passes.
struct CallTotals {
  std::array<unsigned long long, kCounterCount> counters{};
  std::uint64_t to_device = 0, to_host = 0;
  int launches = 0;
  int replays = 0;           ///< launches discarded for a missing brick (a distributed field)
  std::uint64_t bricks = 0;  ///< a distributed field's bricks copied to the device
};

/// A distributed field's renders on one DeviceScene, one at a time: holds its pool's mutex
/// for the call (a pool left stale by a failed call emptied first) and adds the bricks'
/// traffic of the call to `t` when it ends. Nothing for other fields.
class BrickLock {
 public:
  BrickLock(const DeviceScene& dev, CallTotals& t) : m_bricks(dev.bricks()), m_t(t) {
    if (!m_bricks) return;
    m_lock = std::unique_lock(dev.bricks_mutex());
    if (!m_bricks->valid()) m_bricks->reset();
    m_to_device = m_bricks->bytes_to_device();
    m_to_host = m_bricks->bytes_to_host();
    m_fetched = m_bricks->fetched();
  }
  ~BrickLock() {
    if (!m_bricks) return;
    m_t.to_device += m_bricks->bytes_to_device() - m_to_device;
    m_t.to_host += m_bricks->bytes_to_host() - m_to_host;
    m_t.bricks += m_bricks->fetched() - m_fetched;
  }
  BrickLock(const BrickLock&) = delete;
  BrickLock& operator=(const BrickLock&) = delete;

 private:
  DeviceBricks* m_bricks;
  CallTotals& m_t;
  std::unique_lock<std::mutex> m_lock;
  std::uint64_t m_to_device = 0, m_to_host = 0, m_fetched = 0;
};

/// One pass of samples on the device: the jobs, their sums before the pass (which set each
/// job's first sample index, PixelSums::drawn) and after it, `lanes` lanes per job, and which
/// samples: ranges[i] = {k, count}: the pass's samples [previous k, k) of jobs [0, count)
/// (ranges in increasing k, counts not increasing).
struct SamplePass {
  std::vector<PixelJob> jobs;
  std::vector<PixelSums> px;
  std::vector<AuxSums> aux;  ///< empty: no denoiser features
  int lanes = 1;
  std::vector<std::pair<int, std::int64_t>> ranges;

  /// Device bytes of the pass's buffers with `with_lanes` lanes (0: its own); `replayed`: a
  /// distributed field's, whose launches keep a copy of their lanes' sums and counters to
  /// restore when they are run again (replay_slice).
  std::uint64_t device_bytes(int with_lanes = 0, bool replayed = false) const {
    const std::uint64_t l = static_cast<std::uint64_t>(with_lanes > 0 ? with_lanes : lanes);
    const std::uint64_t sums = sizeof(PixelSums) + (aux.empty() ? 0 : sizeof(AuxSums));
    const std::uint64_t per_job = sizeof(PixelJob) + (1 + l) * sums + (replayed ? l * sums : 0);
    return jobs.size() * per_job + (replayed ? 2 : 1) * kCounterCount * sizeof(unsigned long long);
  }
};

/// The adaptive preview's pass (adaptive_sampling.h): the middle pixel of every block of the
/// image (preview_pixel), its pilot samples from index kPreviewIndexBase, in one lane (its sums
/// added in index order, as the host's preview adds them); neighbours' jobs, whose samples are
/// not the image's.
SamplePass preview_pass(const KernelScene& ks, int pilot) {
  SamplePass p;
  const int rows = adaptive_blocks(ks.height);
  const int cols = adaptive_blocks(ks.width);
  for (int by = 0; by < rows; ++by)
    for (int bx = 0; bx < cols; ++bx) {
      int x = 0, y = 0;
      preview_pixel(bx, by, ks.width, ks.height, &x, &y);
      p.jobs.push_back({x, y, kJobNeighbour});
    }
  PixelSums start;
  start.drawn = kPreviewIndexBase;
  p.px.assign(p.jobs.size(), start);
  p.lanes = 1;
  p.ranges = {{pilot, static_cast<std::int64_t>(p.jobs.size())}};
  return p;
}

/// Runs `p` in bounded slices (the deadline checked between them), merges its lanes and
/// copies its sums back into p.px / p.aux (also when stopped: they hold the samples drawn)
/// and its counters into `t`. True when the deadline stopped it.
bool run_pass(DeviceBackend& b, const DeviceScene& dev, const KernelScene& ks, SamplePass& p, const CudaLaunch& launch,
              StopCheck& stop, CallTotals& t) {
  const auto njobs = static_cast<std::int64_t>(p.jobs.size());
  const int lanes = p.lanes;
  const bool with_aux = !p.aux.empty();
  std::array<unsigned long long, kCounterCount> counters{};
  BackendBuffer d_jobs(b), d_px(b), d_aux(b), d_counters(b), d_lane_px(b), d_lane_aux(b);
  t.to_device += d_jobs.upload(p.jobs.data(), p.jobs.size() * sizeof(PixelJob), "pixel list");
  t.to_device += d_px.upload(p.px.data(), p.px.size() * sizeof(PixelSums), "pixel sums");
  if (with_aux) t.to_device += d_aux.upload(p.aux.data(), p.aux.size() * sizeof(AuxSums), "auxiliary sums");
  t.to_device += d_counters.upload(counters.data(), sizeof(counters), "counters");
  d_lane_px.allocate(p.jobs.size() * lanes * sizeof(PixelSums), "sample lanes' sums");
  b.zero(d_lane_px.get(), d_lane_px.bytes(), "sample lanes' sums");
  if (with_aux) {
    d_lane_aux.allocate(p.jobs.size() * lanes * sizeof(AuxSums), "sample lanes' auxiliary sums");
    b.zero(d_lane_aux.get(), d_lane_aux.bytes(), "sample lanes' auxiliary sums");
  }
  // A distributed field: room to restore a launch's sums and counters (replay_slice)
  DeviceBricks* const bricks = dev.bricks();
  BackendBuffer keep_px(b), keep_aux(b), keep_counters(b);
  if (bricks) {
    keep_px.allocate(p.jobs.size() * lanes * sizeof(PixelSums), "sample lanes' sums (kept for a replay)");
    if (with_aux) keep_aux.allocate(p.jobs.size() * lanes * sizeof(AuxSums), "sample lanes' sums (kept for a replay)");
    keep_counters.allocate(sizeof(counters), "counters (kept for a replay)");
  }

  // The lanes' path slots when the backend's loop keeps them in device memory (the wavefront)
  BackendBuffer scratch(b);
  if (const std::size_t bytes = b.slice_scratch_bytes(ks, njobs * lanes); bytes > 0)
    scratch.allocate(bytes, "path slots of the wavefront loop");

  // Bounded slices: the jobs' next few samples at a time; each lane's samples are drawn and
  // added in index order whatever the slicing
  bool stopped = false;
  int k_begin = 0;
  for (const auto& [k_end, count] : p.ranges) {
    const std::int64_t per_launch_px =
        launch.pixels_per_launch > 0 ? launch.pixels_per_launch : std::max<std::int64_t>(count, 1);
    const int span = k_end - k_begin;
    const int per_launch_spp = launch.samples_per_launch > 0
                                   ? launch.samples_per_launch
                                   : static_cast<int>(std::clamp<std::int64_t>(
                                         kDefaultSamplesPerLaunch / std::max<std::int64_t>(count, 1), 1, span));
    for (int s0 = k_begin; s0 < k_end && !stopped; s0 += per_launch_spp) {
      for (std::int64_t j0 = 0; j0 < count; j0 += per_launch_px) {
        if (stop.stop()) {
          stopped = true;
          break;
        }
        const SliceArgs a{dev.kernel(),
                          dev.medium(),
                          d_jobs.as<PixelJob>(),
                          d_px.as<PixelSums>(),
                          d_lane_px.as<PixelSums>(),
                          with_aux ? d_lane_aux.as<AuxSums>() : nullptr,
                          d_counters.as<unsigned long long>(),
                          j0,
                          std::min(count, j0 + per_launch_px),
                          s0,
                          std::min(k_end, s0 + per_launch_spp),
                          lanes,
                          nullptr,
                          nullptr,
                          scratch.get()};
        const std::string name = pixel_kernel_name(ks) + " slice (samples " + std::to_string(s0) + "+, pixels " +
                                 std::to_string(j0) + "+ of " + std::to_string(count) + ")";
        if (!bricks) {
          b.run_slice(dev.dispatch_scene(), a, launch.block_threads, name);
          ++t.launches;
        } else if (!replay_slice(
                       b, *bricks, dev.dispatch_scene(), a,
                       {keep_px.as<PixelSums>(), keep_aux.as<AuxSums>(), keep_counters.as<unsigned long long>()},
                       launch, stop, name, t.launches, t.replays)) {
          stopped = true;
          break;
        }
      }
    }
    if (stopped) break;
    k_begin = k_end;
  }

  // The lanes into the pixels (also after a deadline: the sums hold the samples drawn), then
  // the sums and counters back
  b.merge_lanes(d_px.as<PixelSums>(), with_aux ? d_aux.as<AuxSums>() : nullptr, d_lane_px.as<PixelSums>(),
                with_aux ? d_lane_aux.as<AuxSums>() : nullptr, njobs, lanes);
  b.copy_to_host(p.px.data(), d_px.get(), p.px.size() * sizeof(PixelSums), "pixel sums");
  t.to_host += p.px.size() * sizeof(PixelSums);
  if (with_aux) {
    b.copy_to_host(p.aux.data(), d_aux.get(), p.aux.size() * sizeof(AuxSums), "auxiliary sums");
    t.to_host += p.aux.size() * sizeof(AuxSums);
  }
  b.copy_to_host(counters.data(), d_counters.get(), sizeof(counters), "counters");
  t.to_host += sizeof(counters);
  for (int i = 0; i < kCounterCount; ++i)
    t.counters[static_cast<std::size_t>(i)] += counters[static_cast<std::size_t>(i)];
  return stopped;
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

  const int spp = s.kernel.spp;
  const int lanes = sample_lanes(s.desc.image.width, s.desc.image.height, spp);
  const bool with_aux = film.has_aux();
  const bool adaptive = s.kernel.target_error > 0.0;
  const bool paged = s.kernel.paged.cache != nullptr;
  CallTotals totals;
  StopCheck stop(s.desc.options.deadline);
  std::shared_ptr<DeviceScene> dev;
  bool reused = false;
  std::uint64_t device_bytes = 0;
  bool stopped = false;
  if (!adaptive) {
    // Uniform sampling: the tiles' pixels continue from their sums so far (sample indices
    // from PixelSums::drawn), spp each, and their sums replace the film's
    SamplePass pass;
    pass.jobs = pixel_jobs(s, tile_indices);
    pass.px.resize(pass.jobs.size());
    pass.aux.resize(with_aux ? pass.jobs.size() : 0);
    for (std::size_t j = 0; j < pass.jobs.size(); ++j) {
      pass.px[j] = film.at(pass.jobs[j].x, pass.jobs[j].y);
      if (with_aux) pass.aux[j] = *film.aux_at(pass.jobs[j].x, pass.jobs[j].y);
    }
    pass.lanes = lanes;
    pass.ranges = {{spp, static_cast<std::int64_t>(pass.jobs.size())}};
    const std::uint64_t bytes = pass.device_bytes(0, paged) +
                                b.slice_scratch_bytes(s.kernel, static_cast<std::int64_t>(pass.jobs.size()) * lanes);
    dev = device_scene(backend, s, launch, bytes, &totals.to_device, &device_bytes, &reused);
    const BrickLock bricks(*dev, totals);
    stopped = run_pass(b, *dev, s.kernel, pass, launch, stop, totals);
    for (std::size_t j = 0; j < pass.jobs.size(); ++j) {
      film.at(pass.jobs[j].x, pass.jobs[j].y) = pass.px[j];
      if (with_aux) *film.aux_at(pass.jobs[j].x, pass.jobs[j].y) = pass.aux[j];
    }
  } else {
    // Adaptive sampling (adaptive_plan.h): the pilot of every block pixel one lane each (so
    // its sums are added in index order, as the CPU pools them), then the rest of each own
    // pixel's count; every pixel's samples have indices 0..n-1, and the sums are added to
    // the film's, as sample_adaptive does
    const int pilot = adaptive_pilot(spp);
    SamplePass first;
    AdaptivePilot plan = adaptive_pilot_jobs(s, tile_indices);
    first.jobs = std::move(plan.jobs);
    first.px.resize(first.jobs.size());
    first.aux.resize(with_aux ? first.jobs.size() : 0);
    first.lanes = 1;
    first.ranges = {{pilot, static_cast<std::int64_t>(first.jobs.size())}};
    // A GPU render's preview (PreparedSceneImpl::preview_on_device) first, over the whole
    // image, as prepare makes it on the host; its counters are not the render's (nor are the
    // host preview's), its copies and launches are
    SamplePass preview;
    if (s.preview_on_device) preview = preview_pass(s.kernel, pilot);
    // The second pass's buffers are at most the first's with `lanes` lanes (>= 1)
    const std::int64_t threads =
        std::max(static_cast<std::int64_t>(first.jobs.size()) * lanes, static_cast<std::int64_t>(preview.jobs.size()));
    const std::uint64_t bytes = std::max(first.device_bytes(lanes, paged), preview.device_bytes(1, paged)) +
                                b.slice_scratch_bytes(s.kernel, threads);
    dev = device_scene(backend, s, launch, bytes, &totals.to_device, &device_bytes, &reused);
    const BrickLock bricks(*dev, totals);
    double scale = s.kernel.adaptive_scale;
    if (s.preview_on_device) {
      CallTotals uncounted;
      stopped = run_pass(b, *dev, s.kernel, preview, launch, stop, uncounted);
      totals.to_device += uncounted.to_device;
      totals.to_host += uncounted.to_host;
      totals.launches += uncounted.launches;
      totals.replays += uncounted.replays;
      std::vector<PilotSums> blocks(preview.px.size());
      for (std::size_t j = 0; j < blocks.size(); ++j)
        blocks[j] = {preview.px[j].lum, preview.px[j].lum2, preview.px[j].n};
      preview = {};
      scale = preview_scale(blocks, adaptive_blocks(s.kernel.width), s.kernel.target_error);
    }
    if (!stopped) stopped = run_pass(b, *dev, s.kernel, first, launch, stop, totals);
    // The own pixels with their pilot sums: after a deadline in the pilot, what it drew; else
    // most samples first, so that samples [m_i-1, m_i) of the call's sample indices past the
    // pilot are drawn by the pixels with m >= m_i, a prefix
    std::vector<std::size_t> order;
    for (std::size_t j = 0; j < first.jobs.size(); ++j)
      if (first.jobs[j].culled != kJobNeighbour) order.push_back(j);
    std::vector<int> n;
    if (!stopped) {
      n = adaptive_counts(plan.block_start, first.jobs, first.px, pilot, spp, scale);
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t c) { return n[a] > n[c]; });
    }
    plan = {};
    SamplePass rest;
    for (const std::size_t j : order) {
      rest.jobs.push_back(first.jobs[j]);
      rest.px.push_back(first.px[j]);
      if (with_aux) rest.aux.push_back(first.aux[j]);
    }
    first = {};
    if (!stopped) {
      for (std::size_t i = order.size(); i-- > 0;) {
        const int more = n[order[i]] - pilot;
        if (more > 0 && (rest.ranges.empty() || rest.ranges.back().first < more))
          rest.ranges.push_back({more, static_cast<std::int64_t>(i + 1)});
      }
      rest.lanes = lanes;
      stopped = run_pass(b, *dev, s.kernel, rest, launch, stop, totals);
    }
    for (std::size_t j = 0; j < rest.jobs.size(); ++j) {
      add_sums(film.at(rest.jobs[j].x, rest.jobs[j].y), rest.px[j]);
      if (with_aux) add_sums(*film.aux_at(rest.jobs[j].x, rest.jobs[j].y), rest.aux[j]);
    }
  }

  const auto& counters = totals.counters;
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
    transfer->bytes_to_device = totals.to_device;
    transfer->bytes_to_host = totals.to_host;
    transfer->device_bytes = device_bytes;
    transfer->field_in_place = dev->field_in_place();
    transfer->scene_reused = reused;
    transfer->launches = totals.launches;
    transfer->replays = totals.replays;
    transfer->bricks = totals.bricks;
  }
  if (stopped) throw DeadlineExceeded(0, tile_indices.size());
}

}  // namespace tessera::cuda
