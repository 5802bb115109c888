// warp_model: how busy a GPU warp's threads would be on a scene, modelled on the CPU.
//
// The CUDA kernel (docs/gpu.md) runs a pixel's L sample lanes (sample_lanes: 32 at 128x128 and
// 256 spp) as neighbouring threads, one warp. A warp runs one instruction for all its threads,
// so a thread whose path is shorter than its neighbours' waits. This program traces every
// sample of a scene's render with the kernel's own code (TileSampler::start/step, one bounce at
// a time), records each bounce's tracking steps (free-flight and transmittance lookups), runs
// them again on the step-level loop (PathSteps) recording each iteration's lookups, and
// replays the pixel's lanes as a warp under six loop designs:
//   per-sample  : each lane traces one sample's whole path, then the next (the default kernel);
//                 a bounce's free-flight loop runs as long as its longest lane, then its
//                 shadow loop, and a sample as long as its longest path.
//   regenerate  : one bounce per iteration, a lane's next sample starting when its path ends
//                 (-DTESSERA_CUDA_PATH_REGEN=ON).
//   step        : one tracking step per iteration whatever the lane's phase, ideally: the warp
//                 runs as long as its busiest lane's steps.
//   step (built): the step-level loop as built (-DTESSERA_CUDA_STEP_LOOP=ON, PathSteps): each
//                 lane's loop iterations replayed in lockstep. An iteration costs the most
//                 lookups any lane took in it (a call may end a walk and take the next walk's
//                 first step), at least 1, plus the overhead when some lane ended a flight.
//   step-defer  : the built loop with the code after a flight deferred until half the live
//                 lanes wait for it (or none can step), then run by those lanes together
//                 (the warp vote of -DTESSERA_CUDA_STEP_DEFER=ON): a tracking step costs 1,
//                 that code the overhead.
//   wavefront   : the lanes' paths in `--slots N` path slots, rounds of two kernels over
//                 compacted queues (-DTESSERA_CUDA_WAVEFRONT=ON): the code between walks of the
//                 slots whose walk ended, then at most `--wave-steps S` tracking steps of every
//                 walk (wavefront_steps; N and S default to the kernel's). Its warps hold any
//                 lanes of the image, the other designs' one pixel's lanes.
// "Active lanes" is the lanes' useful steps over the warp's steps: the figure Nsight Compute
// reports as active threads per warp instruction. Each bounce also costs `--overhead K` steps
// (the collision's shading and sampling, the same for every lane). The model ignores the
// divergence inside a bounce's non-tracking code and memory latency.
//
//   warp_model SCENE.yaml [--render NAME] [--image W H] [--spp S] [--overhead K] [--slots N] [--wave-steps S]
//              [--csv FILE]
#include <tessera/config/config.h>
#include <tessera/config/raw_volume.h>
#include <tessera/job/args.h>
#include <tessera/job/render_job.h>
#include <tessera/render.h>

#include "cuda/pixel_kernel.h"
#include "kernel/kernel_dispatch.h"
#include "kernels/tile_sampler.h"
#include "kernels/wave_scratch.h"
#include "scene/prepared_scene_impl.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using tessera::KernelScene;

/// One bounce's tracking steps: free flight, and the shadow rays' transmittance.
struct Bounce {
  std::uint32_t flight = 0, shadow = 0;
};

/// A lane's samples in order, each its bounces.
using Lane = std::vector<std::vector<Bounce>>;

/// One loop iteration of a lane of the built step-level loop: its tracking lookups, and
/// whether a free flight ended in it (a collision's shading or a path's end).
struct StepCall {
  std::uint32_t lookups = 0;
  bool bounce = false;
};

/// Warp steps of the designs, and the lanes' useful steps, for one pixel.
struct WarpSteps {
  double work = 0, per_sample = 0, regenerate = 0, step = 0, built = 0, deferred = 0;
  void add(const WarpSteps& o) {
    deferred += o.deferred;
    work += o.work;
    per_sample += o.per_sample;
    regenerate += o.regenerate;
    step += o.step;
    built += o.built;
  }
};

/// The built loop's iterations with the code between walks deferred: a lane whose flight has
/// ended waits until at least `share` of the live lanes wait (or none can step), then the
/// waiting lanes run that code together (LaneLoop::StepDefer's warp vote). Each lane's items:
/// a tracking step (cost 1) or the code after a flight (cost `overhead`).
double deferred_steps(const std::vector<std::vector<StepCall>>& lanes, double overhead, double share) {
  const std::size_t n = lanes.size();
  std::vector<std::size_t> call(n, 0);
  std::vector<char> pending(n, 0);  // the lane's current call: its step taken, its flight's end not yet run
  double w = 0;
  for (;;) {
    std::size_t live = 0, waiting = 0;
    for (std::size_t q = 0; q < n; ++q) {
      if (call[q] >= lanes[q].size() && !pending[q]) continue;
      ++live;
      waiting += pending[q] ? 1 : 0;
    }
    if (live == 0) return w;
    if (waiting > 0 && (waiting == live || static_cast<double>(waiting) >= share * static_cast<double>(live))) {
      for (std::size_t q = 0; q < n; ++q) pending[q] = 0;
      w += overhead;
      continue;
    }
    for (std::size_t q = 0; q < n; ++q)
      if (!pending[q] && call[q] < lanes[q].size()) pending[q] = lanes[q][call[q]++].bounce ? 1 : 0;
    w += 1;
  }
}

/// The built step-level loop's warp steps: the lanes' iterations in lockstep.
double built_steps(const std::vector<std::vector<StepCall>>& lanes, double overhead) {
  std::size_t longest = 0;
  for (const auto& l : lanes) longest = std::max(longest, l.size());
  double w = 0;
  for (std::size_t i = 0; i < longest; ++i) {
    std::uint32_t most = 1;
    bool bounce = false;
    for (const auto& l : lanes)
      if (i < l.size()) {
        most = std::max(most, l[i].lookups);
        bounce = bounce || l[i].bounce;
      }
    w += most + (bounce ? overhead : 0.0);
  }
  return w;
}

/// One iteration of a bounce loop over the lanes' bounces `b` (null: the lane is idle): the
/// free-flight loop as long as its longest lane, then the shadow loop, plus the overhead.
template <class Get>
double bounce_steps(int lanes, Get&& b, double overhead) {
  std::uint32_t f = 0, s = 0;
  bool any = false;
  for (int l = 0; l < lanes; ++l)
    if (const Bounce* x = b(l)) {
      f = std::max(f, x->flight);
      s = std::max(s, x->shadow);
      any = true;
    }
  return any ? f + s + overhead : 0.0;
}

WarpSteps replay(const std::vector<Lane>& lanes, double overhead) {
  const int n = static_cast<int>(lanes.size());
  WarpSteps w;
  std::size_t samples = 0;
  for (const Lane& l : lanes) samples = std::max(samples, l.size());
  // per sample: the lanes' s-th samples together, bounce by bounce
  for (std::size_t s = 0; s < samples; ++s) {
    std::size_t depth = 0;
    for (const Lane& l : lanes)
      if (s < l.size()) depth = std::max(depth, l[s].size());
    for (std::size_t i = 0; i < depth; ++i)
      w.per_sample += bounce_steps(
          n,
          [&](int q) -> const Bounce* {
            const Lane& l = lanes[static_cast<std::size_t>(q)];
            return s < l.size() && i < l[s].size() ? &l[s][i] : nullptr;
          },
          overhead);
  }
  // regenerate: each lane's bounces one after the other, whatever sample they belong to
  std::vector<std::vector<const Bounce*>> flat(lanes.size());
  std::size_t longest = 0;
  for (std::size_t q = 0; q < lanes.size(); ++q) {
    double total = 0;
    for (const auto& sample : lanes[q])
      for (const Bounce& b : sample) {
        flat[q].push_back(&b);
        total += b.flight + b.shadow + overhead;
      }
    longest = std::max(longest, flat[q].size());
    w.work += total;
    w.step = std::max(w.step, total);  // step: the busiest lane's steps
  }
  for (std::size_t i = 0; i < longest; ++i)
    w.regenerate += bounce_steps(
        n,
        [&](int q) -> const Bounce* {
          const auto& f = flat[static_cast<std::size_t>(q)];
          return i < f.size() ? f[i] : nullptr;
        },
        overhead);
  return w;
}

/// Traces pixel (x, y)'s samples 0..spp-1 lane by lane (sample k on lane k mod lanes), one
/// bounce at a time with the kernel's TileSampler, recording each bounce's lookups.
template <class V>
std::vector<Lane> trace_pixel(const KernelScene& ks, const tessera::GridMedium<V>& medium, bool culled, int x, int y,
                              int lanes) {
  tessera::TileSampler<V> ts(ks, medium, culled, nullptr);
  std::vector<Lane> out(static_cast<std::size_t>(lanes));
  tessera::PixelSums px;
  tessera::AuxSums aux;
  tessera::RenderStats st;
  typename tessera::TileSampler<V>::Flight f;
  for (int k = 0; k < ks.spp; ++k) {
    std::vector<Bounce>& sample = out[static_cast<std::size_t>(k % lanes)].emplace_back();
    ts.start(x, y, px, static_cast<std::uint64_t>(k), st, f);
    while (f.live) {
      const tessera::RenderStats& c = ts.counters();
      const std::uint64_t f0 = c.free_flight_lookups, s0 = c.transmittance_lookups;
      ts.step(f);
      sample.push_back({static_cast<std::uint32_t>(c.free_flight_lookups - f0),
                        static_cast<std::uint32_t>(c.transmittance_lookups - s0)});
    }
    if (sample.empty()) sample.push_back({});  // a culled sample: one iteration of overhead
    ts.finish(f, px, &aux, st);
  }
  return out;
}

/// Runs pixel (x, y)'s samples on the built step-level loop, lane by lane as draw_lane does
/// (lane_kernel.h: a lane's next sample starts in the iteration after its path ended; a culled
/// sample takes one iteration), recording each iteration's lookups.
template <class V>
std::vector<std::vector<StepCall>> trace_pixel_steps(const KernelScene& ks, const tessera::GridMedium<V>& medium,
                                                     bool culled, int x, int y, int lanes) {
  tessera::TileSampler<V> ts(ks, medium, culled, nullptr);
  std::vector<std::vector<StepCall>> out(static_cast<std::size_t>(lanes));
  tessera::PixelSums px;
  tessera::AuxSums aux;
  tessera::RenderStats st;
  for (int lane = 0; lane < lanes; ++lane) {
    typename tessera::TileSampler<V>::StepFlight f;
    auto& calls = out[static_cast<std::size_t>(lane)];
    for (int k = lane;;) {
      if (!f.live) {
        if (k >= ks.spp) break;
        ts.start(x, y, px, static_cast<std::uint64_t>(k), st, f);
        k += lanes;
        if (!f.live) {
          ts.finish(f, px, &aux, st);
          calls.push_back({0, true});
          continue;
        }
      }
      const tessera::RenderStats& c = ts.counters();
      const std::uint64_t l0 = c.free_flight_lookups + c.transmittance_lookups, r0 = c.real_collisions;
      const bool live = ts.step(f);
      calls.push_back({static_cast<std::uint32_t>(c.free_flight_lookups + c.transmittance_lookups - l0),
                       !live || c.real_collisions != r0});
      if (!live) ts.finish(f, px, &aux, st);
    }
  }
  return out;
}

/// A lane's walks in order: each bounce's free flight, then its shadow rays (0: no walk, the
/// code between walks goes on), for the wavefront's replay.
std::vector<std::uint32_t> lane_walks(const Lane& l) {
  std::vector<std::uint32_t> w;
  for (const auto& sample : l)
    for (const Bounce& b : sample) {
      w.push_back(b.flight);
      w.push_back(b.shadow);
    }
  return w;
}

/// The wavefront (-DTESSERA_CUDA_WAVEFRONT=ON, kernels/wave_kernel.h) replayed over all the
/// image's lanes: `slots` path slots, each taking the next lane when its lane's walks are done,
/// and rounds of two kernels: the code between walks of the slots whose walk has ended,
/// compacted in slot order into warps of 32 (a slot's piece of code, `overhead`/2, before each
/// walk; a warp runs as long as its busiest slot), then up to `steps`
/// tracking steps of every walk, compacted in slot order into warps of 32 (a warp runs as long
/// as its longest walk, or `steps`; a walk without lookups, through empty cells, costs one); a
/// walk not ended goes on in the next round.
double wavefront_steps(const std::vector<std::vector<std::uint32_t>>& lanes, std::size_t slots, double overhead,
                       std::uint32_t steps, std::size_t* rounds) {
  *rounds = 0;
  struct Slot {
    std::size_t lane = 0, item = 0;
    std::uint32_t left = 0;  ///< steps left of the current walk
    bool has = false, done = false;
  };
  std::vector<Slot> s(std::max<std::size_t>(1, std::min(slots, lanes.size())));
  std::size_t next = 0;
  double w = 0;
  std::vector<Slot*> queue;
  for (;;) {
    queue.clear();
    std::uint32_t warp_pieces = 0;
    int in_warp = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      Slot& x = s[i];
      std::uint32_t pieces = 0;
      while (!x.done && x.left == 0) {
        if (!x.has) {
          if (next >= lanes.size()) {
            x.done = true;
            break;
          }
          x = {next++, 0, 0, true, false};
        }
        const auto& items = lanes[x.lane];
        if (x.item >= items.size()) {
          x.has = false;
          continue;
        }
        ++pieces;
        x.left = std::max<std::uint32_t>(1, items[x.item++]);  // (a walk without lookups still steps)
      }
      if (x.left > 0) queue.push_back(&x);
      if (pieces == 0) continue;  // (a slot in a walk, or done: not in the between queue)
      warp_pieces = std::max(warp_pieces, pieces);
      if (++in_warp == 32) {
        w += 0.5 * overhead * warp_pieces;
        warp_pieces = 0;
        in_warp = 0;
      }
    }
    w += 0.5 * overhead * warp_pieces;
    if (queue.empty()) return w;
    ++*rounds;
    for (std::size_t q = 0; q < queue.size(); q += 32) {
      std::uint32_t most = 0;
      for (std::size_t r = q; r < std::min(queue.size(), q + 32); ++r) {
        const std::uint32_t take = std::min(steps, queue[r]->left);
        queue[r]->left -= take;
        most = std::max(most, take);
      }
      w += most;
    }
  }
}

}  // namespace

int main(int argc, char** argv) try {
  std::string scene, render, csv;
  int width = 0, height = 0, spp = 0;
  double overhead = 0.0;
  std::size_t slots = static_cast<std::size_t>(tessera::cuda::kWaveSlots);
  auto wave_steps = static_cast<std::uint32_t>(tessera::cuda::kWaveSteps);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    const auto positive = [&]() {
      const int v = std::stoi(next());
      if (v < 1) throw std::invalid_argument(a + " takes positive numbers");
      return v;
    };
    if (a == "--render") render = next();
    else if (a == "--image") {
      width = positive();
      height = positive();
    } else if (a == "--spp") spp = positive();
    else if (a == "--overhead") overhead = std::stod(next());
    else if (a == "--csv") csv = next();
    else if (a == "--slots") slots = static_cast<std::size_t>(positive());
    else if (a == "--wave-steps") wave_steps = static_cast<std::uint32_t>(positive());
    else if (scene.empty() && a.rfind("--", 0) != 0) scene = a;
    else throw std::invalid_argument("unknown argument " + a);
  }
  if (!(overhead >= 0.0 && overhead < 1e9)) throw std::invalid_argument("--overhead takes a number in [0, 1e9)");
  if (scene.empty())
    throw std::invalid_argument(
        "usage: warp_model SCENE.yaml [--render NAME] [--image W H] [--spp S] [--overhead K] [--slots N] "
        "[--wave-steps S] [--csv FILE]");
  const tessera::config::Config cfg = tessera::config::load_config(scene);
  if (!cfg.volume) throw std::invalid_argument(scene + ": no volume block");
  const tessera::config::RenderSpec* spec = render.empty() ? &cfg.renders.back() : cfg.find_render(render);
  if (!spec) throw std::invalid_argument(scene + ": no render '" + render + "'");
  const tessera::config::RawVolume volume = tessera::config::load_raw_volume(*cfg.volume);
  tessera::job::VolumeInfo info = tessera::job::describe_volume(volume, *cfg.volume, spec->integrator.desc);
  tessera::job::Args args;
  if (width > 0) args.width = width;
  if (height > 0) args.height = height;
  if (spp > 0) args.spp = spp;
  const tessera::SceneDesc desc = tessera::job::scene_for(cfg, *spec, info, args);
  const tessera::PreparedScene ps = tessera::prepare(info.view, desc, info.summary);
  const tessera::PreparedSceneImpl& impl = tessera::prepared_scene_impl(ps);
  const KernelScene& ks = impl.kernel;
  const int lanes = tessera::cuda::sample_lanes(ks.width, ks.height, ks.spp);
  // Each pixel's culling verdict (its tile's)
  std::vector<char> culled(static_cast<std::size_t>(ks.width) * ks.height);
  for (std::size_t t = 0; t < impl.tiles.size(); ++t)
    for (int y = impl.tiles[t].y0; y < impl.tiles[t].y1; ++y)
      for (int x = impl.tiles[t].x0; x < impl.tiles[t].x1; ++x)
        culled[static_cast<std::size_t>(y) * ks.width + x] = impl.tile_culled[t];
  std::vector<WarpSteps> rows(static_cast<std::size_t>(ks.height));
  // Every lane's walks, in the kernel's thread order (pixel by pixel, its lanes side by side)
  std::vector<std::vector<std::uint32_t>> walks(static_cast<std::size_t>(ks.width) * ks.height * lanes);
  tessera::with_value(ks, [&](auto tag) {
    using V = typename decltype(tag)::type;
    using Base = typename tessera::ValueTraits<V>::base;
    if constexpr (std::is_same_v<Base, tessera::MeshValue> || std::is_same_v<Base, tessera::PagedValue>) {
      throw std::invalid_argument("warp_model: meshes and paged fields are not modelled");
    } else {
      const tessera::GridMedium<V> medium = tessera::make_medium<V>(ks);
      tbb::parallel_for(0, ks.height, [&](int y) {
        for (int x = 0; x < ks.width; ++x) {
          const bool c = culled[static_cast<std::size_t>(y) * ks.width + x] != 0;
          const std::vector<Lane> traced = trace_pixel<V>(ks, medium, c, x, y, lanes);
          for (int l = 0; l < lanes; ++l)
            walks[(static_cast<std::size_t>(y) * ks.width + x) * lanes + l] = lane_walks(traced[l]);
          WarpSteps w = replay(traced, overhead);
          const auto calls = trace_pixel_steps<V>(ks, medium, c, x, y, lanes);
          w.built = built_steps(calls, overhead);
          w.deferred = deferred_steps(calls, overhead, 0.5);
          rows[static_cast<std::size_t>(y)].add(w);
        }
      });
    }
  });
  WarpSteps t;
  for (const WarpSteps& r : rows) t.add(r);
  // (the other designs' warps are a pixel's lanes; the wavefront's, 32 slots of the image's)
  std::size_t rounds = 0;
  const double wave = wavefront_steps(walks, slots, overhead, wave_steps, &rounds);
  const auto active = [&](double steps) { return steps > 0 ? t.work / steps : 0.0; };
  std::printf("%s, render '%s': %dx%d, %d spp, %d lanes per pixel, overhead %g steps per bounce\n", scene.c_str(),
              spec->name.c_str(), ks.width, ks.height, ks.spp, lanes, overhead);
  std::printf("  %-11s %14s %13s\n", "loop", "warp steps", "active lanes");
  const std::pair<const char*, double> loops[] = {
      {"per-sample", t.per_sample}, {"regenerate", t.regenerate}, {"step", t.step},
      {"step-built", t.built},      {"step-defer", t.deferred},   {"wavefront", wave}};
  for (const auto& [name, steps] : loops) std::printf("  %-11s %14.4g %8.2f / %d\n", name, steps, active(steps), lanes);
  std::printf("  (wavefront: %zu slots, at most %u tracking steps a walk per round, %zu rounds)\n",
              std::min(slots, walks.size()), wave_steps, rounds);
  if (!csv.empty()) {
    FILE* f = std::fopen(csv.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + csv);
    std::fprintf(f, "scene,render,width,height,spp,lanes,overhead,loop,warp_steps,active_lanes\n");
    for (const auto& [name, steps] : loops)
      std::fprintf(f, "%s,%s,%d,%d,%d,%d,%g,%s,%.6g,%.4f\n", scene.c_str(), spec->name.c_str(), ks.width, ks.height,
                   ks.spp, lanes, overhead, name, steps, active(steps));
    std::fclose(f);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "warp_model: %s\n", e.what());
  return 1;
}
