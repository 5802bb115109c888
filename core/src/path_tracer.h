#pragma once
/// PathTracer<T, S, kEmission>: the per-sample estimator of docs/physics.md, templated on the
/// field's element type, the shading mode and whether an emission TF exists, so the hot loop
/// holds no code for what the scene does not use. Allocates nothing, throws nothing.
#include <tessera/loop_bounds.h>
#include <tessera/stats.h>

#include "grid_medium.h"
#include "phase_hg.h"
#include "prepared_scene_impl.h"
#include "sampling/rng.h"
#include "stop_check.h"
#include "surface_brdf.h"

#include <algorithm>
#include <cmath>

namespace tessera {

/// The estimator counts into RenderStats' own fields (free_flight_lookups, real_collisions,
/// stalled_paths, ...), so a tile's counts reach the render's with RenderStats::add_counters.
using KernelCounters = RenderStats;

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
inline double power_heuristic(double pa, double pb) {
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

/// Unit-rate exponential sample -log(1 - u): 1 - u is exact for u = k 2^-53, so log() loses
/// nothing against log1p(-u) here and costs about half as much (it is on every tracking step).
inline double exp_unit(Rng& rng) { return -std::log(1.0 - rng.uniform()); }
inline double exp_sample(Rng& rng, double rate) { return exp_unit(rng) / rate; }

template <class V, Shading S, bool kEmission>
class PathTracer {
 public:
  /// `stop`, when given, is polled every kStopPollBounces collisions of a path; once it says
  /// stop the path ends there (the render is then failed by its caller, never written).
  PathTracer(const PreparedSceneImpl& s, const GridMedium<V>& m, StopCheck* stop = nullptr)
      : m_s(s), m_m(m), m_stop(stop) {}

  SampleResult li(Ray ray, Rng& rng, KernelCounters& k) const {
    const IntegratorDesc& in = m_s.desc.integrator;
    // Single scattering is the path tracer with one real collision (spec section 6).
    const int max_depth = in.scattering == Scattering::Single ? 1 : in.max_bounces;
    SampleResult out;
    Color beta(1.0);
    bool from_camera = true;
    double pdf_prev = 0.0;  // solid-angle pdf of the direction that made `ray`
    for (int depth = 0;;) {
      // Free flight to the next real collision (or none).
      double t_hit = INFINITY;
      bool stalled = false;
      const bool hit = free_flight(ray, rng, k, &t_hit, &stalled);
      if (stalled) break;  // a loop guard ended the path: nothing more from it
      // Lights met before the collision, and the background if the ray escaped.
      gather_emitters(ray, t_hit, hit, from_camera, pdf_prev, beta, out.L);
      if (!hit) break;
      if (from_camera) out.alpha = 1.0;
      ++depth;
      // A long path polls the render's deadline now and then (the render then fails)
      if ((depth & (kStopPollBounces - 1)) == 0 && m_stop && m_stop->stop()) break;
      ++k.real_collisions;
      const Vec3 x = ray.o + t_hit * ray.d;
      const Vec3 pv = to_voxel(x);
      const double u = m_m.u(pv);
      if constexpr (kEmission) out.L += beta * m_s.desc.tf.emission.eval(u);
      // Choose the scattering model at this point.
      const Vec3 wo = -ray.d;
      const Color albedo = m_s.desc.tf.diffuse.eval(u);
      bool surface = false;
      Vec3 normal(0.0);
      if constexpr (S != Shading::Phase) {
        const Vec3 gv = m_m.gradient_voxel(pv);
        k.gradient_lookups += 6;
        const double gmag = glm::length(gv);
        if (gmag > 0.0) {
          const Vec3 gw = gv * m_s.inv_spacing;  // world-space direction of grad u
          const double gwl = glm::length(gw);
          if (gwl > 0.0) {
            normal = -gw / gwl;
            if (glm::dot(normal, wo) < 0.0) normal = -normal;
            if constexpr (S == Shading::Brdf) {
              surface = true;
            } else {
              const double p_brdf = 1.0 - std::exp(-in.gradient_factor * gmag);
              surface = rng.uniform() < p_brdf;
            }
          }
        }
      }
      if (from_camera) {
        out.albedo = glm::clamp(albedo, Color(0.0), Color(1.0));
        out.normal = normal;
      }
      const Color f0 = surface && m_s.has_specular ? m_s.desc.tf.specular.eval(u) : Color(0.0);
      const double rough = surface ? m_s.desc.tf.roughness.eval(u) : 0.0;
      const SurfaceBrdf brdf(normal, albedo, f0, rough);
      // Next-event estimation to one light, MIS-weighted against phase/BRDF sampling.
      if (m_s.light_count > 0) out.L += beta * direct_light(x, ray.d, wo, surface, brdf, albedo, rng, k);
      // Sample the continuation direction.
      Vec3 wi;
      double pdf_dir;
      Color weight;
      if (surface) {
        const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
        if (!brdf.sample(wo, u0, u1, u2, &wi)) break;
        pdf_dir = brdf.pdf(wo, wi);
        if (!(pdf_dir > 0.0)) break;
        weight = brdf.eval(wo, wi) / pdf_dir;
      } else {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        pdf_dir = hg_sample(ray.d, in.phase_g, u1, u2, &wi);
        weight = albedo;
      }
      beta *= weight;
      if (is_black(beta)) break;
      const Ray next{x, wi};
      if (depth >= max_depth) {
        // Last collision: the sampled direction only gathers emitters, with transmittance.
        gather_with_transmittance(next, pdf_dir, beta, rng, k, out.L);
        break;
      }
      if (depth >= in.rr_depth) {
        const double q = max_component(beta);
        if (q < 1.0) {
          if (rng.uniform() >= q) break;
          beta /= q;
        }
      }
      ray = next;
      pdf_prev = pdf_dir;
      from_camera = false;
    }
    return out;
  }

 private:
  const PreparedSceneImpl& m_s;
  const GridMedium<V>& m_m;
  StopCheck* m_stop;

  Vec3 to_voxel(const Vec3& x) const { return (x - m_s.desc.geometry.origin) * m_s.inv_spacing; }

  /// Ray/box clip in voxel space; returns false if the ray misses the box or it is degenerate.
  bool clip(const Vec3& ov, const Vec3& dv, double* t0, double* t1) const {
    double a = 0.0, b = INFINITY;
    for (int ax = 0; ax < 3; ++ax) {
      const double hi = m_m.hi_index[ax];
      if (dv[ax] == 0.0) {
        if (ov[ax] < 0.0 || ov[ax] > hi) return false;
        continue;
      }
      double ta = (0.0 - ov[ax]) / dv[ax], tb = (hi - ov[ax]) / dv[ax];
      if (ta > tb) std::swap(ta, tb);
      a = std::max(a, ta);
      b = std::min(b, tb);
    }
    *t0 = a;
    *t1 = b;
    return a < b;
  }

  /// Ends the path for a loop guard: counted once, *stalled set.
  static bool stall(KernelCounters& k, bool* stalled) {
    ++k.stalled_paths;
    *stalled = true;
    return true;
  }

  /// Free-flight sampling along the ray: delta tracking against the majorant grid, or the
  /// biased fixed-step march. True and *t_hit on a real collision. Loop guards: a ray the
  /// box clip leaves unbounded (zero or NaN direction), a step that does not advance t, or a
  /// traversal over its step budget (loop_bounds.h) sets *stalled and returns false.
  bool free_flight(const Ray& ray, Rng& rng, KernelCounters& k, double* t_hit, bool* stalled) const {
    const Vec3 ov = to_voxel(ray.o), dv = ray.d * m_s.inv_spacing;
    double t0, t1;
    if (!clip(ov, dv, &t0, &t1) || m_s.grid.max_majorant() <= 0.0) return false;
    if (!(t1 < INFINITY)) return !stall(k, stalled);
    if (m_s.desc.integrator.free_path == FreePath::Raymarch) {
      const double h = m_s.march_step;
      // t only grows, so if the last step advances every step does
      if (!(t1 + h > t1)) return !stall(k, stalled);
      const double tau = exp_unit(rng);
      double sum = 0.0;
      double budget = kMaxMarchSteps + 2.0;
      for (double t = t0 + rng.uniform() * h; t < t1; t += h) {
        if (--budget < 0.0) return !stall(k, stalled);
        ++k.free_flight_lookups;
        sum += m_m.sigma_t(ov + t * dv) * h;
        if (sum >= tau) {
          *t_hit = t;
          return true;
        }
      }
      return false;
    }
    double budget = kMaxTrackingSteps;
    const bool stopped = traverse_macrocells(m_m, ov, dv, t0, t1, [&](double ta, double tb, double maj) {
      if (maj <= 0.0) return false;  // empty cell: crossed in closed form
      for (double t = ta;;) {
        const double dt = exp_sample(rng, maj);
        const double t_next = t + dt;
        if (t_next >= tb) return false;
        if ((!(t_next > t) && dt > 0.0) || --budget < 0.0) return stall(k, stalled);
        t = t_next;
        ++k.free_flight_lookups;
        const double sigma = m_m.sigma_t(ov + t * dv);
        if (rng.uniform() * maj < sigma) {
          *t_hit = t;
          return true;
        }
        ++k.null_collisions;
      }
    });
    return stopped && !*stalled;
  }

  /// Transmittance between world distances ta and tb along the ray (ratio or delta tracking).
  /// The loop guards of free_flight end the estimate at 0 (an occluded shadow ray adds no
  /// light), counted in k.stalled_paths.
  double transmittance(const Ray& ray, double ta, double tb, Rng& rng, KernelCounters& k) const {
    const Vec3 ov = to_voxel(ray.o), dv = ray.d * m_s.inv_spacing;
    double t0, t1;
    if (!clip(ov, dv, &t0, &t1)) return 1.0;
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (!(t0 < t1) || m_s.grid.max_majorant() <= 0.0) return 1.0;
    if (!(t1 < INFINITY)) {
      ++k.stalled_paths;
      return 0.0;
    }
    const bool ratio = m_s.desc.integrator.shadow == ShadowMode::Ratio;
    const bool roulette = m_s.desc.integrator.shadow_roulette;
    double T = 1.0;
    double budget = kMaxTrackingSteps;
    traverse_macrocells(m_m, ov, dv, t0, t1, [&](double a, double b, double maj) {
      if (maj <= 0.0) return false;
      for (double t = a;;) {
        const double dt = exp_sample(rng, maj);
        const double t_next = t + dt;
        if (t_next >= b) return false;
        if ((!(t_next > t) && dt > 0.0) || --budget < 0.0) {
          ++k.stalled_paths;
          T = 0.0;
          return true;
        }
        t = t_next;
        ++k.transmittance_lookups;
        const double sigma = m_m.sigma_t(ov + t * dv);
        if (ratio) {
          T *= 1.0 - sigma / maj;
          if (roulette && T < 0.1) {
            if (rng.uniform() < 0.5) T = 0.0;
            else T *= 2.0;
          }
        } else if (rng.uniform() * maj < sigma) {
          T = 0.0;
        }
        if (T <= 0.0) return true;
      }
    });
    return std::max(T, 0.0);
  }

  double light_select_pdf() const { return 1.0 / m_s.light_count; }

  /// Emitters met along `ray` before distance t_end (all lights are transparent), plus the
  /// background when the ray escaped, MIS-weighted against light sampling unless from the camera.
  void gather_emitters(const Ray& ray, double t_end, bool hit, bool from_camera, double pdf_prev,
                       const Color& beta, Color& L) const {
    const double psel = m_s.light_count > 0 ? light_select_pdf() : 0.0;
    for (const RectLight& l : m_s.rects) {
      const double t = l.intersect_front(ray);
      if (t > 0.0 && t < t_end) {
        const double w = from_camera ? 1.0 : power_heuristic(pdf_prev, psel * l.pdf(ray.o, ray.d, t));
        L += beta * l.radiance() * w;
      }
    }
    for (const SphereLight& l : m_s.spheres) {
      const double t = l.intersect_front(ray);
      if (t > 0.0 && t < t_end) {
        const double w = from_camera ? 1.0 : power_heuristic(pdf_prev, psel * l.pdf(ray.o, ray.d, t));
        L += beta * l.radiance() * w;
      }
    }
    if (!hit) {
      if (from_camera) {
        if (m_s.env.visible()) L += beta * m_s.env.eval(ray.d);
      } else if (m_s.env.emits()) {
        L += beta * m_s.env.eval(ray.d) * power_heuristic(pdf_prev, psel * m_s.env.pdf(ray.d));
      }
    }
  }

  /// Like gather_emitters for the last collision's sampled direction, where no further free
  /// flight is sampled: each emitter is weighted by the transmittance up to it.
  void gather_with_transmittance(const Ray& ray, double pdf_dir, const Color& beta, Rng& rng,
                                 KernelCounters& k, Color& L) const {
    if (m_s.light_count == 0) return;
    struct Hit { double t; Color Le; double pdf; };
    Hit hits[kMaxLights];
    int n = 0;
    const double psel = light_select_pdf();
    for (const RectLight& l : m_s.rects) {
      const double t = l.intersect_front(ray);
      if (t > 0.0) hits[n++] = {t, l.radiance(), psel * l.pdf(ray.o, ray.d, t)};
    }
    for (const SphereLight& l : m_s.spheres) {
      const double t = l.intersect_front(ray);
      if (t > 0.0) hits[n++] = {t, l.radiance(), psel * l.pdf(ray.o, ray.d, t)};
    }
    std::sort(hits, hits + n, [](const Hit& a, const Hit& b) { return a.t < b.t; });
    double T = 1.0, t_prev = 0.0;
    for (int i = 0; i < n && T > 0.0; ++i) {
      T *= transmittance(ray, t_prev, hits[i].t, rng, k);
      t_prev = hits[i].t;
      if (T > 0.0) L += beta * hits[i].Le * (T * power_heuristic(pdf_dir, hits[i].pdf));
    }
    if (m_s.env.emits() && T > 0.0) {
      T *= transmittance(ray, t_prev, INFINITY, rng, k);
      if (T > 0.0)
        L += beta * m_s.env.eval(ray.d) * (T * power_heuristic(pdf_dir, psel * m_s.env.pdf(ray.d)));
    }
  }

  /// Next-event estimation to one light chosen uniformly (background included when it emits).
  Color direct_light(const Vec3& x, const Vec3& d_in, const Vec3& wo, bool surface,
                     const SurfaceBrdf& brdf, const Color& albedo, Rng& rng,
                     KernelCounters& k) const {
    const int nl = m_s.light_count;
    const int nrect = static_cast<int>(m_s.rects.size()), nsph = static_cast<int>(m_s.spheres.size());
    const int pick = std::min(nl - 1, static_cast<int>(rng.uniform() * nl));
    const double u1 = rng.uniform(), u2 = rng.uniform();
    LightSample ls;
    if (pick < nrect) {
      ls = m_s.rects[pick].sample(x, u1, u2);
    } else if (pick < nrect + nsph) {
      ls = m_s.spheres[pick - nrect].sample(x, u1, u2);
    } else {
      double pdf;
      Vec3 wi;
      const Color Le = m_s.env.sample(u1, u2, &wi, &pdf);
      ls = LightSample{wi, INFINITY, Le, pdf};
    }
    if (!(ls.pdf > 0.0) || is_black(ls.L)) return Color(0.0);
    const double pdf_light = ls.pdf * light_select_pdf();
    Color f;
    double pdf_b;
    if (surface) {
      f = brdf.eval(wo, ls.wi);
      pdf_b = brdf.pdf(wo, ls.wi);
    } else {
      const double p = hg_eval(glm::dot(d_in, ls.wi), m_s.desc.integrator.phase_g);
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
