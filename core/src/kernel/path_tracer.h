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

  /// One bounce of path `p`: free flight to the next real collision, the emitters met, and
  /// at the collision next-event estimation and the next direction. False when the path has
  /// ended (p.out is then its sample).
  TESSERA_HOST_DEVICE bool bounce(PathState& p, Rng& rng, KernelCounters& k, const SobolSampler* ld) const {
    const TransferFunction& tf = *m_s.tf;
    Ray& ray = p.ray;
    SampleResult& out = p.out;
    Color& beta = p.beta;
    bool& from_camera = p.from_camera;
    double& pdf_prev = p.pdf_prev;
    int& depth = p.depth;
    // Free flight to the next real collision (or none).
    double t_hit = INFINITY;
    bool stalled = false;
    const bool hit = free_flight(ray, rng, k, &t_hit, &stalled);
    if (stalled) return false;  // a loop guard ended the path: nothing more from it
    // Lights met before the collision, and the background if the ray escaped.
    gather_emitters(ray, t_hit, hit, from_camera, pdf_prev, beta, out.L);
    if (!hit) return false;
    if (from_camera) out.alpha = 1.0;
    ++depth;
    // A long path polls the render's deadline now and then (the render then fails)
    if ((depth & (kStopPollBounces - 1)) == 0 && poll_stop()) return false;
    ++k.real_collisions;
    const Vec3 x = ray.o + t_hit * ray.d;
    const Vec3 pv = to_voxel(x);
    const double u = m_m.u(pv);
    if (m_s.has_emission) out.L += beta * tf.emission.eval(u);
    const SobolSampler* first = from_camera ? ld : nullptr;  // the first collision's sampler, if any
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
    if (from_camera) {
      out.albedo = glm::clamp(albedo, Color(0.0), Color(1.0));
      out.normal = normal;
    }
    const Color f0 = surface && m_s.has_specular ? tf.specular.eval(u) : Color(0.0);
    const double rough = surface ? tf.roughness.eval(u) : 0.0;
    const SurfaceBrdf brdf(normal, albedo, f0, rough);
    // Next-event estimation to one light, MIS-weighted against phase/BRDF sampling.
    if (m_L.count() > 0) out.L += beta * direct_light(x, ray.d, wo, surface, brdf, albedo, first, rng, k);
    // Sample the continuation direction.
    Vec3 wi;
    double pdf_dir;
    Color weight;
    if (surface) {
      const double u0 = sample_1d(first, SampleDim::Lobe, rng);
      const Sample2 u = sample_2d(first, SampleDim::Direction, rng);
      if (!brdf.sample(wo, u0, u.x, u.y, &wi)) return false;
      pdf_dir = brdf.pdf(wo, wi);
      if (!(pdf_dir > 0.0)) return false;
      weight = brdf.eval(wo, wi) / pdf_dir;
    } else {
      const Sample2 u = sample_2d(first, SampleDim::Direction, rng);
      pdf_dir = hg_sample(ray.d, m_s.phase_g, u.x, u.y, &wi);
      weight = albedo;
    }
    beta *= weight;
    if (is_black(beta)) return false;
    const Ray next{x, wi};
    if (depth >= m_s.max_depth) {
      // Last collision: the sampled direction only gathers emitters, with transmittance.
      gather_with_transmittance(next, pdf_dir, beta, rng, k, out.L);
      return false;
    }
    if (depth >= m_s.rr_depth) {
      const double q = max_component(beta);
      if (q < 1.0) {
        if (rng.uniform() >= q) return false;
        beta /= q;
      }
    }
    ray = next;
    pdf_prev = pdf_dir;
    from_camera = false;
    return true;
  }

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

  /// Ends the path for a loop guard: counted once, *stalled set.
  TESSERA_HOST_DEVICE static bool stall(KernelCounters& k, bool* stalled) {
    ++k.stalled_paths;
    *stalled = true;
    return true;
  }

  /// Free-flight sampling along the ray: delta tracking on the tracking loop (tracking.h),
  /// or the biased fixed-step march, as the scene's free_path says (one branch per ray). True
  /// and *t_hit on a real collision. Loop guards: a ray the box clip leaves unbounded (zero or
  /// NaN direction), a step that does not advance t, or a traversal over its step budget
  /// (loop_bounds.h) sets *stalled and returns false.
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE bool free_flight(const Ray& ray, Rng& rng, KernelCounters& k,
                                                               double* t_hit, bool* stalled) const {
    const Vec3 ov = to_voxel(ray.o), dv = ray.d * m_s.inv_spacing;
    double t0, t1;
    if (!clip(ov, dv, &t0, &t1) || m_s.max_majorant <= 0.0) return false;
    if (!(t1 < INFINITY)) return !stall(k, stalled);
    if (m_s.free_path == FreePath::Raymarch) {
      const double h = m_s.march_step;
      // t only grows, so if the last step advances every step does
      if (!(t1 + h > t1)) return !stall(k, stalled);
      const int r = march_free_flight(m_m, ov, dv, t0, t1, h, rng, t_hit, [&] { ++k.free_flight_lookups; });
      if (r < 0) return !stall(k, stalled);
      return r > 0;
    } else {
      const TrackEnd end = sample_majorant_steps(
          m_m, ov, dv, t0, t1, rng, [&](const Vec3& p, double t, double maj) __attribute__((always_inline)) {
            ++k.free_flight_lookups;
            if (rng.uniform() * maj < m_m.sigma_t(p)) {
              *t_hit = t;
              return false;  // a real collision
            }
            ++k.null_collisions;
            return true;
          });
      if (end == TrackEnd::Stalled) return !stall(k, stalled);
      return end == TrackEnd::Stopped;
    }
  }

  /// Transmittance between world distances ta and tb along the ray, by the scene's shadow
  /// estimator on the tracking loop (shadow_walk, one branch per ray). The loop guards of
  /// free_flight end the estimate at 0 (an occluded shadow ray adds no light), counted in
  /// k.stalled_paths.
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE double transmittance(const Ray& ray, double ta, double tb, Rng& rng,
                                                                   KernelCounters& k) const {
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
    double T = 1.0;
    const TrackEnd end = m_s.shadow == ShadowMode::Delta ? shadow_walk<ShadowMode::Delta>(ov, dv, t0, t1, rng, k, T)
                                                         : shadow_walk<ShadowMode::Ratio>(ov, dv, t0, t1, rng, k, T);
    if (end == TrackEnd::Stalled) {
      ++k.stalled_paths;
      T = 0.0;
    }
    return std::max(T, 0.0);
  }

  /// The tracking loop of one shadow estimator over voxel-space ray ov + t dv, t in [t0, t1],
  /// updating the transmittance estimate T at each tentative collision.
  template <ShadowMode kMode>
  TESSERA_HOST_DEVICE TrackEnd shadow_walk(const Vec3& ov, const Vec3& dv, double t0, double t1, Rng& rng,
                                           KernelCounters& k, double& T) const {
    const bool roulette = m_s.shadow_roulette;
    return sample_majorant_steps(
        m_m, ov, dv, t0, t1, rng, [&](const Vec3& p, double, double maj) __attribute__((always_inline)) {
          ++k.transmittance_lookups;
          TransmittanceStep<kMode>::apply(T, m_m.sigma_t(p), maj, roulette, rng);
          return !(T <= 0.0);
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
      int next = -1;  // the first light after (t_prev, last) in (distance, index) order
      for (int i = 0; i < n; ++i) {
        const double t = t_hit[i];
        if (!(t > 0.0) || t < t_prev || (t == t_prev && i <= last)) continue;
        if (next < 0 || t < t_hit[next]) next = i;
      }
      if (next < 0) break;
      T *= transmittance(ray, t_prev, t_hit[next], rng, k);
      t_prev = t_hit[next];
      last = next;
      if (T > 0.0) {
        const Light& l = m_L[next];
        L += beta * l.radiance(ray.d) *
             (T * power_heuristic(pdf_dir, m_L.sampler().pmf(next) * l.pdf(ray.o, ray.d, t_prev)));
      }
    }
    // The infinite lights, behind everything: one transmittance estimate to infinity
    if (m_L.area_count() < m_L.count() && T > 0.0) {
      T *= transmittance(ray, t_prev, INFINITY, rng, k);
      if (!(T > 0.0)) return;
      for (int i = m_L.area_count(); i < m_L.count(); ++i) {
        const Light& l = m_L[i];
        L += beta * l.radiance(ray.d) *
             (T * power_heuristic(pdf_dir, m_L.sampler().pmf(i) * l.pdf(ray.o, ray.d, INFINITY)));
      }
    }
  }

  /// Next-event estimation to one light chosen by the light sampler; the pick and the light
  /// sample from `ld` when given (li).
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE Color direct_light(const Vec3& x, const Vec3& d_in, const Vec3& wo,
                                                                 bool surface, const SurfaceBrdf& brdf,
                                                                 const Color& albedo, const SobolSampler* ld, Rng& rng,
                                                                 KernelCounters& k) const {
    const int pick = ld && m_L.count() == 1 ? 0 : m_L.sampler().pick(sample_1d(ld, SampleDim::LightPick, rng));
    const Sample2 u = sample_2d(ld, SampleDim::LightUv, rng);
    const LightSample ls = m_L[pick].sample(x, u.x, u.y);
    if (!(ls.pdf > 0.0) || is_black(ls.L)) return Color(0.0);
    const double pdf_light = ls.pdf * m_L.sampler().pmf(pick);
    Color f;
    double pdf_b;
    if (surface) {
      f = brdf.eval(wo, ls.wi);
      pdf_b = brdf.pdf(wo, ls.wi);
    } else {
      const double p = hg_eval(glm::dot(d_in, ls.wi), m_s.phase_g);
      f = albedo * p;
      pdf_b = p;
    }
    if (is_black(f)) return Color(0.0);
    const double T = transmittance(Ray{x, ls.wi}, 0.0, ls.dist, rng, k);
    if (T <= 0.0) return Color(0.0);
    return f * ls.L * (T * power_heuristic(pdf_light, pdf_b) / pdf_light);
  }
};

}  // namespace tessera
