#pragma once
/// PathTracer<V>: the per-sample estimator of docs/physics.md, templated on the field's Value
/// (kernel_dispatch.h), so the field lookups hold no branch on the dtype. The frame's modes
/// are read from the KernelScene once per ray or collision, never per tracking step: the
/// free-path strategy and the shadow estimator each pick one of two loops compiled apart
/// (a template on the estimator), the shading mode and the emission TF only change what a
/// real collision evaluates. Reads a KernelScene and its LightSet only: it names no concrete
/// light type. Allocates nothing, throws nothing.
#include <tessera/loop_bounds.h>
#include <tessera/stats.h>

#include "kernel/grid_medium.h"
#include "kernel/kernel_scene.h"
#include "kernel/phase_hg.h"
#include "kernel/stop_check.h"
#include "kernel/surface_brdf.h"
#include "kernel/tracking.h"
#include "sampling/rng.h"
#include "sampling/sobol_sampler.h"

#include <algorithm>
#include <cmath>

namespace tessera {

/// The estimator counts into RenderStats' own fields (free_flight_lookups, real_collisions,
/// stalled_paths, ...), so a tile's counts reach the render's with RenderStats::add_counters.
using KernelCounters = RenderStats;

/// What one camera sample returns: radiance and alpha (1 once the path met the medium).
/// With the first real collision's albedo and normal, the denoiser's features (image.denoise).
struct SampleResult {
  Color L{0.0};
  double alpha = 0.0;
  /// The denoiser's features at the camera ray's first real collision (0 if none): the
  /// diffuse TF colour clamped to [0, 1], and the shading normal (unit, facing the camera;
  /// 0 where the shading has no gradient normal: phase shading or a zero gradient).
  Color albedo{0.0};
  Vec3 normal{0.0};
};

/// Power-heuristic weight pa^2 / (pa^2 + pb^2); 0 when both are 0 or either is NaN. When a
/// square overflows (a tiny light's pdf is huge, or infinite once its solid angle underflows)
/// the same weight from the ratio of the two, so that inf / inf never makes a NaN sample.
TESSERA_HOST_DEVICE inline double power_heuristic(double pa, double pb) {
  const double a2 = pa * pa, b2 = pb * pb;
  const double sum = a2 + b2;
  if (sum < INFINITY) return sum > 0.0 ? a2 / sum : 0.0;
  if (!(sum > 0.0) || pa != pa || pb != pb) return 0.0;  // NaN
  if (pa == pb) return 0.5;
  if (pa > pb) {
    const double r = pb / pa;  // 0 when pa is infinite
    return 1.0 / (1.0 + r * r);
  }
  const double r = pa / pb;
  return r * r / (1.0 + r * r);
}

template <class V>
class PathTracer {
 public:
  /// `stop`, when given, is polled every kStopPollBounces collisions of a path; once it says
  /// stop the path ends there (the render is then failed by its caller, never written).
  TESSERA_HOST_DEVICE PathTracer(const KernelScene& s, const GridMedium<V>& m, StopCheck* stop = nullptr)
      : m_s(s), m_m(m), m_L(s.lights), m_stop(stop) {}

  /// One camera sample's radiance along `ray`. With `ld`, the first real collision's light
  /// pick and light sample, hybrid choice and direction sample come from it (sobol_sampler.h);
  /// everything else, and all of them without it, from `rng`. The path one bounce at a time
  /// (begin, bounce): a caller that interleaves paths gets the same values.
  TESSERA_HOST_DEVICE SampleResult li(Ray ray, Rng& rng, KernelCounters& k, const SobolSampler* ld = nullptr) const {
    PathState p = begin(ray);
    while (bounce(p, rng, k, ld)) {
    }
    return p.out;
  }

  /// A path in flight: what one bounce hands the next.
  struct PathState {
    Ray ray;
    SampleResult out;
    Color beta{1.0};
    bool from_camera = true;
    double pdf_prev = 0.0;  ///< solid-angle pdf of the direction that made `ray`
    int depth = 0;          ///< real collisions so far
  };

  /// The path of a camera ray, before its first free flight.
  TESSERA_HOST_DEVICE static PathState begin(const Ray& ray) {
    PathState p;
    p.ray = ray;
    return p;
  }

  /// What a real collision hands next-event estimation and the path's next direction.
  struct Scatter {
    Vec3 x{0.0}, wo{0.0};
    SurfaceBrdf brdf;
    Color albedo{0.0};
    bool surface = false;
    bool first = false;  ///< the camera ray's first collision: its samples from `ld` when given
  };

  /// Next-event estimation's light sample, waiting for the transmittance of its shadow ray.
  struct LightPending {
    Ray shadow{Vec3(0.0), Vec3(0.0, 0.0, 1.0)};  ///< from the collision toward the light
    double dist = 0.0;                           ///< the light's distance along `shadow`
    Color fL{0.0};                               ///< scattering function x the light's radiance
    double weight = 0.0;                         ///< MIS weight against phase/BRDF sampling
    double pdf_light = 0.0;                      ///< the sample's pdf, light pick included
  };

  /// A voxel-space ray ov + t dv and the world distances [t0, t1] a majorant walk covers.
  struct Span {
    Vec3 ov{0.0}, dv{0.0};
    double t0 = 0.0, t1 = 0.0;
  };

  /// How free flight starts (flight_begin): ended at once, or a majorant walk to follow.
  enum class FlightStart { Miss, Hit, Stalled, Walk };
  /// What follows a collision's direction sample (scatter).
  enum class Next { End, Last, Continue };

  /// One bounce of path `p`: free flight to the next real collision, the emitters met, and
  /// at the collision next-event estimation and the next direction. False when the path has
  /// ended (p.out is then its sample). The pieces (free_flight's two halves, collide,
  /// sample_light, transmittance's two halves, light_arrived, scatter, the last bounce's
  /// emitters) are public for a caller that runs them one tracking step at a time
  /// (path_steps.h): the same operations in the same order.
  TESSERA_HOST_DEVICE bool bounce(PathState& p, Rng& rng, KernelCounters& k, const SobolSampler* ld) const {
    double t_hit = INFINITY;
    bool stalled = false;
    const bool hit = free_flight(p.ray, rng, k, &t_hit, &stalled);
    if (stalled) return false;  // a loop guard ended the path: nothing more from it
    Scatter s;
    if (!collide(p, hit, t_hit, rng, k, ld, s)) return false;
    if (m_L.count() > 0) {
      // Next-event estimation to one light, MIS-weighted against phase/BRDF sampling
      LightPending n;
      Color d(0.0);
      if (sample_light(s, p.ray.d, s.first ? ld : nullptr, rng, n))
        d = light_arrived(n, transmittance(n.shadow, 0.0, n.dist, rng, k));
      p.out.L += p.beta * d;
    }
    Ray next;
    double pdf_dir;
    const Next r = scatter(p, s, ld, rng, &next, &pdf_dir);
    // Last collision: the sampled direction only gathers emitters, with transmittance.
    if (r == Next::Last) gather_with_transmittance(next, pdf_dir, p.beta, rng, k, p.out.L);
    return r == Next::Continue;
  }

  /// The end of p's free flight: the lights met before distance t_hit, the background if the
  /// ray escaped, and at a real collision (`hit`) its emission and scattering model (`s`).
  /// False when the path ends here.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE bool collide(PathState& p, bool hit, double t_hit, Rng& rng,
                                                          KernelCounters& k, const SobolSampler* ld, Scatter& s) const {
    const TransferFunction& tf = *m_s.tf;
    const Ray& ray = p.ray;
    SampleResult& out = p.out;
    gather_emitters(ray, t_hit, hit, p.from_camera, p.pdf_prev, p.beta, out.L);
    if (!hit) return false;
    if (p.from_camera) out.alpha = 1.0;
    ++p.depth;
    // A long path polls the render's deadline now and then (the render then fails)
    if ((p.depth & (kStopPollBounces - 1)) == 0 && poll_stop()) return false;
    ++k.real_collisions;
    const Vec3 x = ray.o + t_hit * ray.d;
    const Vec3 pv = to_voxel(x);
    const double u = m_m.u(pv);
    if (m_s.has_emission) out.L += p.beta * tf.emission.eval(u);
    const SobolSampler* first = p.from_camera ? ld : nullptr;  // the first collision's sampler, if any
    // Choose the scattering model at this point.
    const Vec3 wo = -ray.d;
    const Color albedo = tf.diffuse.eval(u);
    bool surface = false;
    Vec3 normal(0.0);
    if (m_s.shading != Shading::Phase) {
      Vec3 gw_local(0.0);  // world-space grad u where some axis is rectilinear
      Vec3 gv;
      if constexpr (GridMedium<V>::kRectilinear) gv = m_m.gradient_local(pv, m_s.inv_spacing, &gw_local);
      else gv = m_m.gradient_voxel(pv);
      k.gradient_lookups += 6;
      const double gmag = glm::length(gv);
      if (gmag > 0.0) {
        const Vec3 gw = GridMedium<V>::kRectilinear ? gw_local : gv * m_s.inv_spacing;  // world-space grad u
        const double gwl = glm::length(gw);
        if (gwl > 0.0) {
          normal = -gw / gwl;
          if (glm::dot(normal, wo) < 0.0) normal = -normal;
          if (m_s.shading == Shading::Brdf) {
            surface = true;
          } else {
            const double p_brdf = 1.0 - std::exp(-m_s.gradient_factor * gmag);
            surface = sample_1d(first, SampleDim::ScatterChoice, rng) < p_brdf;
          }
        }
      }
    }
    if (p.from_camera) {
      out.albedo = glm::clamp(albedo, Color(0.0), Color(1.0));
      out.normal = normal;
    }
    const Color f0 = surface && m_s.has_specular ? tf.specular.eval(u) : Color(0.0);
    const double rough = surface ? tf.roughness.eval(u) : 0.0;
    s.x = x;
    s.wo = wo;
    s.brdf = SurfaceBrdf(normal, albedo, f0, rough);
    s.albedo = albedo;
    s.surface = surface;
    s.first = p.from_camera;
    return true;
  }

  /// Next-event estimation's light sample from collision `s` (ray direction d_in), with its
  /// scattering function and MIS weight: one light chosen by the light sampler, the pick and
  /// the light sample from `ld` when given. False when it adds nothing whatever the
  /// transmittance; else the caller estimates the transmittance along n.shadow up to n.dist.
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE bool sample_light(const Scatter& s, const Vec3& d_in,
                                                                const SobolSampler* ld, Rng& rng,
                                                                LightPending& n) const {
    const int pick = ld && m_L.count() == 1 ? 0 : m_L.sampler().pick(sample_1d(ld, SampleDim::LightPick, rng));
    const Sample2 u = sample_2d(ld, SampleDim::LightUv, rng);
    const LightSample ls = m_L[pick].sample(s.x, u.x, u.y);
    if (!(ls.pdf > 0.0) || is_black(ls.L)) return false;
    const double pdf_light = ls.pdf * m_L.sampler().pmf(pick);
    Color f;
    double pdf_b;
    if (s.surface) {
      f = s.brdf.eval(s.wo, ls.wi);
      pdf_b = s.brdf.pdf(s.wo, ls.wi);
    } else {
      const double p = hg_eval(glm::dot(d_in, ls.wi), m_s.phase_g);
      f = s.albedo * p;
      pdf_b = p;
    }
    if (is_black(f)) return false;
    n.shadow = Ray{s.x, ls.wi};
    n.dist = ls.dist;
    n.fL = f * ls.L;
    n.weight = power_heuristic(pdf_light, pdf_b);
    n.pdf_light = pdf_light;
    return true;
  }

  /// The light sample's contribution (before the path throughput) once its shadow ray's
  /// transmittance T is known.
  TESSERA_HOST_DEVICE static Color light_arrived(const LightPending& n, double T) {
    if (T <= 0.0) return Color(0.0);
    return n.fL * (T * n.weight / n.pdf_light);
  }

  /// The continuation direction at collision `s`, the throughput updated and Russian
  /// roulette applied. Continue: p.ray is the next ray. Last: the path ends at the depth
  /// limit, and its sampled direction (*next, *pdf_dir) only gathers emitters with
  /// transmittance (gather_with_transmittance). End: the path ends.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE Next scatter(PathState& p, const Scatter& s, const SobolSampler* ld,
                                                          Rng& rng, Ray* next, double* pdf_out) const {
    const SobolSampler* first = s.first ? ld : nullptr;
    Vec3 wi;
    double pdf_dir;
    Color weight;
    if (s.surface) {
      const double u0 = sample_1d(first, SampleDim::Lobe, rng);
      const Sample2 u = sample_2d(first, SampleDim::Direction, rng);
      if (!s.brdf.sample(s.wo, u0, u.x, u.y, &wi)) return Next::End;
      pdf_dir = s.brdf.pdf(s.wo, wi);
      if (!(pdf_dir > 0.0)) return Next::End;
      weight = s.brdf.eval(s.wo, wi) / pdf_dir;
    } else {
      const Sample2 u = sample_2d(first, SampleDim::Direction, rng);
      pdf_dir = hg_sample(p.ray.d, m_s.phase_g, u.x, u.y, &wi);
      weight = s.albedo;
    }
    p.beta *= weight;
    if (is_black(p.beta)) return Next::End;
    const Ray nx{s.x, wi};
    if (p.depth >= m_s.max_depth) {
      *next = nx;
      *pdf_out = pdf_dir;
      return Next::Last;
    }
    if (p.depth >= m_s.rr_depth) {
      const double q = max_component(p.beta);
      if (q < 1.0) {
        if (rng.uniform() >= q) return Next::End;
        p.beta /= q;
      }
    }
    p.ray = nx;
    p.pdf_prev = pdf_dir;
    p.from_camera = false;
    return Next::Continue;
  }

  /// Free flight's first half: the ray clipped to the medium. Walk: a majorant walk over *sp
  /// follows (flight_step at each tentative collision); otherwise the flight's result at once
  /// (Hit with *t_hit: the fixed-step march, which runs here whole; Stalled: counted).
  [[gnu::always_inline]] TESSERA_HOST_DEVICE FlightStart flight_begin(const Ray& ray, Rng& rng, KernelCounters& k,
                                                                      Span* sp, double* t_hit) const {
    const Vec3 ov = to_voxel(ray.o), dv = ray.d * m_s.inv_spacing;
    double t0, t1;
    if (!clip(ov, dv, &t0, &t1) || m_s.max_majorant <= 0.0) return FlightStart::Miss;
    if (!(t1 < INFINITY)) return stall(k);
    if (m_s.free_path == FreePath::Raymarch) {
      const double h = m_s.march_step;
      // t only grows, so if the last step advances every step does
      if (!(t1 + h > t1)) return stall(k);
      const int r = march_free_flight(m_m, ov, dv, t0, t1, h, rng, t_hit, [&] { ++k.free_flight_lookups; });
      if (r < 0) return stall(k);
      return r > 0 ? FlightStart::Hit : FlightStart::Miss;
    }
    *sp = Span{ov, dv, t0, t1};
    return FlightStart::Walk;
  }

  /// Delta tracking's test at a tentative collision at voxel-space p with majorant maj: true
  /// for a real collision.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE bool flight_step(const Vec3& p, double maj, Rng& rng,
                                                              KernelCounters& k) const {
    ++k.free_flight_lookups;
    if (rng.uniform() * maj < m_m.sigma_t(p)) return true;
    ++k.null_collisions;
    return false;
  }

  /// Transmittance's first half, between world distances ta and tb along the ray: its value
  /// at once (>= 0: 1 when the span misses the medium, 0 for a loop guard, counted in
  /// k.stalled_paths), or -1 when a majorant walk over *sp must estimate it (shadow_step at
  /// each tentative collision, then shadow_end).
  [[gnu::always_inline]] TESSERA_HOST_DEVICE double shadow_begin(const Ray& ray, double ta, double tb,
                                                                 KernelCounters& k, Span* sp) const {
    const Vec3 ov = to_voxel(ray.o), dv = ray.d * m_s.inv_spacing;
    double t0, t1;
    if (!clip(ov, dv, &t0, &t1)) return 1.0;
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (!(t0 < t1) || m_s.max_majorant <= 0.0) return 1.0;
    if (!(t1 < INFINITY)) {
      ++k.stalled_paths;
      return 0.0;
    }
    *sp = Span{ov, dv, t0, t1};
    return -1.0;
  }

  /// One shadow estimator's update of the transmittance estimate T at a tentative collision;
  /// false once T has reached 0 (the walk stops).
  template <ShadowMode kMode>
  [[gnu::always_inline]] TESSERA_HOST_DEVICE bool shadow_step(const Vec3& p, double maj, Rng& rng, KernelCounters& k,
                                                              double& T) const {
    ++k.transmittance_lookups;
    TransmittanceStep<kMode>::apply(T, m_m.sigma_t(p), maj, m_s.shadow_roulette, rng);
    return !(T <= 0.0);
  }

  /// shadow_step of the scene's shadow estimator (one branch per step: for a caller that
  /// cannot keep the estimator as a template parameter between steps).
  TESSERA_HOST_DEVICE bool shadow_update(const Vec3& p, double maj, Rng& rng, KernelCounters& k, double& T) const {
    return m_s.shadow == ShadowMode::Delta ? shadow_step<ShadowMode::Delta>(p, maj, rng, k, T)
                                           : shadow_step<ShadowMode::Ratio>(p, maj, rng, k, T);
  }

  /// The estimate once the walk has ended: 0 (counted) if a loop guard ended it.
  TESSERA_HOST_DEVICE static double shadow_end(bool stalled, double T, KernelCounters& k) {
    if (stalled) {
      ++k.stalled_paths;
      T = 0.0;
    }
    return std::max(T, 0.0);
  }

  /// The majorant walk over a span.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE MajorantSteps<V> walk(const Span& sp) const {
    return MajorantSteps<V>(m_m, sp.ov, sp.dv, sp.t0, sp.t1);
  }

  /// The area light the last bounce's ray `ray` meets next after distance t_prev (and after
  /// light `last` at t_prev), in (distance, index) order, with `dist(i)` light i's distance
  /// along the ray (not > 0: missed); -1 when none is left.
  template <class Dist>
  TESSERA_HOST_DEVICE int next_light(double t_prev, int last, Dist&& dist) const {
    int next = -1;
    double t_next = 0.0;
    for (int i = 0; i < m_L.area_count(); ++i) {
      const double t = dist(i);
      if (!(t > 0.0) || t < t_prev || (t == t_prev && i <= last)) continue;
      if (next < 0 || t < t_next) {
        next = i;
        t_next = t;
      }
    }
    return next;
  }

  /// Area light i met at distance t by the last bounce's ray with transmittance T up to it.
  TESSERA_HOST_DEVICE void add_area_light(int i, const Ray& ray, double t, double T, double pdf_dir, const Color& beta,
                                          Color& L) const {
    const Light& l = m_L[i];
    L += beta * l.radiance(ray.d) * (T * power_heuristic(pdf_dir, m_L.sampler().pmf(i) * l.pdf(ray.o, ray.d, t)));
  }

  /// The infinite lights behind everything, seen by the last bounce's ray with transmittance T.
  TESSERA_HOST_DEVICE void add_infinite_lights(const Ray& ray, double T, double pdf_dir, const Color& beta,
                                               Color& L) const {
    for (int i = m_L.area_count(); i < m_L.count(); ++i) {
      const Light& l = m_L[i];
      L += beta * l.radiance(ray.d) *
           (T * power_heuristic(pdf_dir, m_L.sampler().pmf(i) * l.pdf(ray.o, ray.d, INFINITY)));
    }
  }

  TESSERA_HOST_DEVICE const LightSet& lights() const { return m_L; }

 private:
  const KernelScene& m_s;
  const GridMedium<V>& m_m;
  const LightSet m_L;
  StopCheck* m_stop;

  /// The render's deadline, polled by long paths on the host. On the device it is never
  /// polled: the host launches bounded slices and checks the deadline between them.
  TESSERA_HOST_DEVICE bool poll_stop() const {
#if defined(__CUDA_ARCH__)
    return false;
#else
    return m_stop && m_stop->stop();
#endif
  }

  TESSERA_HOST_DEVICE Vec3 to_voxel(const Vec3& x) const { return (x - m_s.origin) * m_s.inv_spacing; }

  /// Ray/box clip in the medium's p space (its box: the cells' box for cell data); returns false if the ray misses the box or it is degenerate.
  TESSERA_HOST_DEVICE bool clip(const Vec3& ov, const Vec3& dv, double* t0, double* t1) const {
    double a = 0.0, b = INFINITY;
    for (int ax = 0; ax < 3; ++ax) {
      const double lo = m_m.box_lo[ax], hi = m_m.box_hi[ax];
      if (dv[ax] == 0.0) {
        if (ov[ax] < lo || ov[ax] > hi) return false;
        continue;
      }
      double ta = (lo - ov[ax]) / dv[ax], tb = (hi - ov[ax]) / dv[ax];
      if (ta > tb) std::swap(ta, tb);
      a = std::max(a, ta);
      b = std::min(b, tb);
    }
    *t0 = a;
    *t1 = b;
    return a < b;
  }

  /// Ends the path for a loop guard: counted once.
  TESSERA_HOST_DEVICE static FlightStart stall(KernelCounters& k) {
    ++k.stalled_paths;
    return FlightStart::Stalled;
  }

  /// Free-flight sampling along the ray: delta tracking on the tracking loop (tracking.h),
  /// or the biased fixed-step march, as the scene's free_path says (one branch per ray). True
  /// and *t_hit on a real collision. Loop guards: a ray the box clip leaves unbounded (zero or
  /// NaN direction), a step that does not advance t, or a traversal over its step budget
  /// (loop_bounds.h) sets *stalled and returns false.
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE bool free_flight(const Ray& ray, Rng& rng, KernelCounters& k,
                                                               double* t_hit, bool* stalled) const {
    Span sp;
    switch (flight_begin(ray, rng, k, &sp, t_hit)) {
      case FlightStart::Miss: return false;
      case FlightStart::Hit: return true;
      case FlightStart::Stalled: *stalled = true; return false;
      case FlightStart::Walk: break;
    }
    const TrackEnd end = sample_majorant_steps(
        m_m, sp.ov, sp.dv, sp.t0, sp.t1, rng, [&](const Vec3& p, double t, double maj) __attribute__((always_inline)) {
          if (!flight_step(p, maj, rng, k)) return true;
          *t_hit = t;
          return false;  // a real collision
        });
    if (end == TrackEnd::Stalled) {
      stall(k);
      *stalled = true;
      return false;
    }
    return end == TrackEnd::Stopped;
  }

  /// Transmittance between world distances ta and tb along the ray, by the scene's shadow
  /// estimator on the tracking loop (shadow_walk, one branch per ray). The loop guards of
  /// free_flight end the estimate at 0 (an occluded shadow ray adds no light), counted in
  /// k.stalled_paths.
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE double transmittance(const Ray& ray, double ta, double tb, Rng& rng,
                                                                   KernelCounters& k) const {
    Span sp;
    const double v = shadow_begin(ray, ta, tb, k, &sp);
    if (v >= 0.0) return v;
    double T = 1.0;
    const TrackEnd end = m_s.shadow == ShadowMode::Delta ? shadow_walk<ShadowMode::Delta>(sp, rng, k, T)
                                                         : shadow_walk<ShadowMode::Ratio>(sp, rng, k, T);
    return shadow_end(end == TrackEnd::Stalled, T, k);
  }

  /// The tracking loop of one shadow estimator over a span, updating the transmittance
  /// estimate T at each tentative collision.
  template <ShadowMode kMode>
  TESSERA_HOST_DEVICE TrackEnd shadow_walk(const Span& sp, Rng& rng, KernelCounters& k, double& T) const {
    return sample_majorant_steps(
        m_m, sp.ov, sp.dv, sp.t0, sp.t1, rng, [&](const Vec3& p, double, double maj) __attribute__((always_inline)) {
          return shadow_step<kMode>(p, maj, rng, k, T);
        });
  }

  /// Emitters met along `ray` before distance t_end (all lights are transparent), plus the
  /// infinite lights when the ray escaped, MIS-weighted against light sampling unless from
  /// the camera (which sees the background as shown, emitting or not).
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE void gather_emitters(const Ray& ray, double t_end, bool hit,
                                                                   bool from_camera, double pdf_prev, const Color& beta,
                                                                   Color& L) const {
    for (int i = 0; i < m_L.area_count(); ++i) {
      const Light& l = m_L[i];
      const double t = l.intersect(ray);
      if (t > 0.0 && t < t_end) {
        const double w = from_camera ? 1.0 : power_heuristic(pdf_prev, m_L.sampler().pmf(i) * l.pdf(ray.o, ray.d, t));
        L += beta * l.radiance(ray.d) * w;
      }
    }
    if (hit) return;
    if (from_camera) {
      if (m_L.background_visible()) L += beta * m_L.background(ray.d);
      return;
    }
    for (int i = m_L.area_count(); i < m_L.count(); ++i) {
      const Light& l = m_L[i];
      L += beta * l.radiance(ray.d) * power_heuristic(pdf_prev, m_L.sampler().pmf(i) * l.pdf(ray.o, ray.d, INFINITY));
    }
  }

  /// Like gather_emitters for the last collision's sampled direction, where no further free
  /// flight is sampled: each emitter is weighted by the transmittance up to it.
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE void gather_with_transmittance(const Ray& ray, double pdf_dir,
                                                                             const Color& beta, Rng& rng,
                                                                             KernelCounters& k, Color& L) const {
    if (m_L.count() == 0) return;
    // Each area light's distance along the ray (not > 0: missed), then the lights met nearest
    // first (equal distances in light order), each weighted by the transmittance up to it.
    // Only the distances are kept (8 bytes a light: on a GPU this array is each thread's
    // stack, reserved for every thread the device can hold).
    double t_hit[kMaxLights];
    const int n = m_L.area_count();
    for (int i = 0; i < n; ++i) t_hit[i] = m_L[i].intersect(ray);
    double T = 1.0, t_prev = 0.0;
    for (int last = -1; T > 0.0;) {
      const int next = next_light(t_prev, last, [&](int i) { return t_hit[i]; });
      if (next < 0) break;
      T *= transmittance(ray, t_prev, t_hit[next], rng, k);
      t_prev = t_hit[next];
      last = next;
      if (T > 0.0) add_area_light(next, ray, t_prev, T, pdf_dir, beta, L);
    }
    // The infinite lights, behind everything: one transmittance estimate to infinity
    if (m_L.area_count() < m_L.count() && T > 0.0) {
      T *= transmittance(ray, t_prev, INFINITY, rng, k);
      if (!(T > 0.0)) return;
      add_infinite_lights(ray, T, pdf_dir, beta, L);
    }
  }
};

}  // namespace tessera
