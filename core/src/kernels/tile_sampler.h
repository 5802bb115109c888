#pragma once
/// TileSampler<V>: one pixel sample, from its random streams to its pixel's sums, shared by
/// the CPU's tile kernels (tile_kernel_impl.h) and the CUDA kernel (core/src/cuda/): the same
/// streams as a function of (seed, frame, pixel, sample index), the same camera ray and
/// estimator, the same sums in the same order. Host and device code; allocates nothing.
#include <tessera/film.h>
#include <tessera/stats.h>

#include "kernel/kernel_scene.h"
#include "kernel/path_steps.h"
#include "kernel/path_tracer.h"
#include "kernel/stop_check.h"

#include <cstdint>

namespace tessera {
namespace {

/// Adds one finite sample to a pixel's sums.
TESSERA_HOST_DEVICE inline void add_sample(PixelSums& px, const SampleResult& r) {
  px.r += r.L.x;
  px.g += r.L.y;
  px.b += r.L.z;
  px.a += r.alpha;
  const double lum = luminance(r.L);
  px.lum += lum;
  px.lum2 += lum * lum;
  ++px.n;
}

/// Adds the kept sample's auxiliary features (the denoiser's albedo and normal) to the
/// pixel's AuxSums, beside add_sample: the same samples in the same order, so the sums are
/// as deterministic as the colour's.
TESSERA_HOST_DEVICE inline void add_aux(AuxSums& aux, const SampleResult& r) {
  for (int c = 0; c < 3; ++c) {
    aux.albedo[c] += r.albedo[c];
    aux.normal[c] += r.normal[c];
  }
}

/// One tile's sampling: draws samples of pixels with the tile's tracer and counters.
template <class V>
class TileSampler {
 public:
  /// `stop`: the render's deadline, polled by long paths (null on the device, which
  /// launches bounded slices instead).
  TESSERA_HOST_DEVICE TileSampler(const KernelScene& s, const GridMedium<V>& medium, bool culled, StopCheck* stop)
      : m_s(s), m_tracer(s, medium, stop), m_culled(culled) {}

  /// Sample `index` of pixel (x, y); false if its radiance is not finite. `own`: the pixel is
  /// in this tile, so the tile's culling applies (another tile's pixel is always traced: a
  /// culled tile's verdict says nothing about its neighbours, and a traced miss gives the
  /// same value as a culled fill).
  TESSERA_HOST_DEVICE bool draw(int x, int y, std::uint64_t index, SampleResult& r, bool own = true) {
    const std::uint64_t pixel = static_cast<std::uint64_t>(y) * m_s.width + x;
    Rng rng(m_s.seed, m_s.frame, pixel, index);
    // The pixel jitter, the lens and the first collision's samples from a scrambled Sobol'
    // sequence when the scene says so (sobol_sampler.h), else from the sample's stream
    if (m_s.sampler == SamplerKind::Sobol) {
      const SobolSampler ld(m_s.seed, m_s.frame, pixel, index);
      return trace(x, y, rng, &ld, own, r);
    }
    return trace(x, y, rng, nullptr, own, r);
  }

  /// Draw sample `index` of the pixel into its sums, and into `aux` when given (a non-finite
  /// one is counted and dropped). Returns the sample when it was kept, for the caller's own
  /// bookkeeping.
  TESSERA_HOST_DEVICE const SampleResult* accumulate(int x, int y, PixelSums& px, AuxSums* aux, std::uint64_t index,
                                                     RenderStats& st) {
    ++st.samples;
    ++px.drawn;
    return keep(m_last, draw(x, y, index, m_last), px, aux, st) ? &m_last : nullptr;
  }

  /// A sample in flight, for a caller that advances it a piece at a time (lane_kernel.h): its
  /// streams, its path, and whether it still runs. Path: PathTracer's PathState, one bounce
  /// per step() (path regeneration), or PathSteps' State, one tracking step per step() (the
  /// step-level loop).
  template <class Path>
  struct FlightOf {
    Rng rng{0, 0, 0, 0};
    SobolSampler ld{0, 0, 0, 0};
    bool has_ld = false;
    bool live = false;  ///< false: the path's out is the sample's value
    /// Set by start() before any read. Not value-initialised (`{}`): nvcc 13 then builds the
    /// empty path as a constant in global memory and copies it through a generic pointer,
    /// which its code generator reports as an invalid bitcast at every kernel it compiles.
    Path path;
  };
  using Flight = FlightOf<typename PathTracer<V>::PathState>;
  using StepFlight = FlightOf<typename PathSteps<V>::State>;

  /// Starts sample `index` of pixel (x, y) in `f` and counts it drawn (accumulate's first
  /// half): the streams, the camera ray and the path before its first bounce, or the value
  /// of a culled tile's ray at once. Then step() until false, then finish(): the same values
  /// and sums as accumulate(), in the same order.
  template <class Path>
  TESSERA_HOST_DEVICE void start(int x, int y, PixelSums& px, std::uint64_t index, RenderStats& st,
                                 FlightOf<Path>& f) const {
    ++st.samples;
    ++px.drawn;
    const std::uint64_t pixel = static_cast<std::uint64_t>(y) * m_s.width + x;
    f.rng = Rng(m_s.seed, m_s.frame, pixel, index);
    f.has_ld = m_s.sampler == SamplerKind::Sobol;
    if (f.has_ld) f.ld = SobolSampler(m_s.seed, m_s.frame, pixel, index);
    const SobolSampler* ld = f.has_ld ? &f.ld : nullptr;
    const Ray ray = camera_ray(x, y, f.rng, ld);
    begin_path(f.path, ray);
    f.live = !m_culled;
    if (m_culled) out(f.path) = culled_value(ray);
  }

  /// One bounce of f's path; false once it has ended (then finish()).
  TESSERA_HOST_DEVICE bool step(Flight& f) {
    f.live = m_tracer.bounce(f.path, f.rng, m_k, f.has_ld ? &f.ld : nullptr);
    return f.live;
  }

  /// One tracking step of f's path, and the code between walks when that step ended its walk
  /// (PathSteps::advance); false once the path has ended (then finish()).
  TESSERA_HOST_DEVICE bool step(StepFlight& f) {
    f.live = PathSteps<V>::advance(m_tracer, f.path, f.rng, m_k, f.has_ld ? &f.ld : nullptr);
    return f.live;
  }

  /// The step-level loop's halves (PathSteps::walking, step, between), for a caller that
  /// defers the code between walks: whether f's path is in a walk; one tracking step of it
  /// (true while the walk goes on); the code between walks (false once the path has ended:
  /// then finish()).
  TESSERA_HOST_DEVICE static bool walking(const StepFlight& f) { return PathSteps<V>::walking(f.path); }
  TESSERA_HOST_DEVICE bool take_step(StepFlight& f) { return PathSteps<V>::step(m_tracer, f.path.w, f.rng, m_k); }
  /// take_step on a path's walk and stream alone (PathSteps::Walk: what a step reads and writes)
  TESSERA_HOST_DEVICE bool take_step(typename PathSteps<V>::Walk& w, Rng& rng) {
    return PathSteps<V>::step(m_tracer, w, rng, m_k);
  }
  TESSERA_HOST_DEVICE bool between(StepFlight& f) {
    f.live = PathSteps<V>::between(m_tracer, f.path, f.rng, m_k, f.has_ld ? &f.ld : nullptr);
    return f.live;
  }

  /// Adds f's ended sample to the pixel's sums as accumulate() does (dropped and counted
  /// when not finite).
  template <class Path>
  TESSERA_HOST_DEVICE void finish(FlightOf<Path>& f, PixelSums& px, AuxSums* aux, RenderStats& st) const {
    const SampleResult& r = out(f.path);
    keep(r, is_finite(r.L), px, aux, st);
  }

  /// Adds the tracer's counts (field lookups, collisions, stalled paths) to `st`.
  void flush(RenderStats& st) const { st.add_counters(m_k); }
  /// The tracer's counts so far (the device adds them to the launch's counters itself).
  TESSERA_HOST_DEVICE const KernelCounters& counters() const { return m_k; }

 private:
  /// The sample's camera ray and its radiance, with the sampler of draw().
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE bool trace(int x, int y, Rng& rng, const SobolSampler* ld, bool own,
                                                         SampleResult& r) {
    const Ray ray = camera_ray(x, y, rng, ld);
    r = m_culled && own ? culled_value(ray) : m_tracer.li(ray, rng, m_k, ld);
    return is_finite(r.L);
  }

  /// A drawn sample into the pixel's sums (and `aux` when given); a non-finite one (`finite`:
  /// is_finite(r.L)) is counted discarded and dropped (false).
  [[gnu::always_inline]] TESSERA_HOST_DEVICE static bool keep(const SampleResult& r, bool finite, PixelSums& px,
                                                              AuxSums* aux, RenderStats& st) {
    if (!finite) {
      ++st.discarded_samples;
      return false;
    }
    add_sample(px, r);
    if (aux) add_aux(*aux, r);
    return true;
  }

  TESSERA_HOST_DEVICE static void begin_path(typename PathTracer<V>::PathState& p, const Ray& ray) {
    p = PathTracer<V>::begin(ray);
  }
  TESSERA_HOST_DEVICE static void begin_path(typename PathSteps<V>::State& p, const Ray& ray) {
    p = PathSteps<V>::begin(ray);
  }
  TESSERA_HOST_DEVICE static SampleResult& out(typename PathTracer<V>::PathState& p) { return p.out; }
  TESSERA_HOST_DEVICE static SampleResult& out(typename PathSteps<V>::State& p) { return p.path.out; }

  /// The camera ray of a sample of pixel (x, y): its pixel jitter and lens sample first.
  TESSERA_HOST_DEVICE Ray camera_ray(int x, int y, Rng& rng, const SobolSampler* ld) const {
    const Sample2 j = sample_2d(ld, SampleDim::Pixel, rng);
    // (a pinhole reads no lens sample: the stream still draws it, as it always has)
    const Sample2 l = ld && m_s.camera.is_pinhole() ? Sample2{0.0, 0.0} : sample_2d(ld, SampleDim::Lens, rng);
    return m_s.camera.generate(x + j.x, y + j.y, l.x, l.y);
  }

  /// A culled tile's rays meet nothing: exactly the background a traced miss returns.
  TESSERA_HOST_DEVICE SampleResult culled_value(const Ray& ray) const {
    return SampleResult{m_s.lights.background_visible() ? m_s.lights.background(ray.d) : Color(0.0), 0.0};
  }

  const KernelScene& m_s;
  const PathTracer<V> m_tracer;
  KernelCounters m_k;
  SampleResult m_last;
  bool m_culled;
};

}  // namespace
}  // namespace tessera
