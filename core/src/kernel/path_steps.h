#pragma once
/// PathSteps<V>: a PathTracer's path run one tracking step at a time, for a GPU thread whose
/// warp should run the same loop body together (the lanes' step-level loop, lane_loop.h):
/// each call takes one tracking step (one tentative collision) of the path's current walk,
/// and when that step ends the walk, runs the code of a bounce between walks up to the start
/// of the next walk (or the path's end). Free flight, the shadow ray of next-event
/// estimation and the last bounce's shadow rays are phases of one state machine over one
/// resumable walk (MajorantSteps), so threads in any of them take the same tentative
/// collision and field lookup at once. The pieces are PathTracer's own (bounce), run in the
/// same order: the same values, rng draws and counters, bit for bit. Allocates nothing,
/// throws nothing; no recursion (the phases are a loop). A caller may also run the two
/// halves itself (step, between: the code between walks deferred, LaneLoop::StepDefer).
#include "kernel/path_tracer.h"
#include "kernel/tracking.h"

#include <cmath>

namespace tessera {

template <class V>
class PathSteps {
 public:
  using Tracer = PathTracer<V>;

  /// Where a path is: in a majorant walk (Flight, Shadow, LastShadow) or between walks.
  enum class Phase : unsigned char {
    StartFlight,  ///< free flight from path.ray to begin
    Flight,       ///< free flight's walk
    Collide,      ///< the flight has ended (hit, t_hit): emitters met, the collision, the light sample
    Shadow,       ///< the light sample's shadow walk
    Lit,          ///< the light sample's transmittance T is known
    Scatter,      ///< the next direction
    Gather,       ///< the last bounce: the next emitter along last_ray
    LastShadow,   ///< the last bounce's walk up to that emitter
    LastLit,      ///< that walk's transmittance T is known
    Ended,        ///< path.out is the sample
  };

  /// The part of a path a tracking step reads and writes (step()): its walk, where it is, and
  /// what the walk has found so far, so that a caller that runs walks apart (the wavefront,
  /// kernels/wave_kernel.h) moves only this. Trivially copyable.
  struct Walk {
    MajorantSteps<V> steps;
    double t_hit = INFINITY;  ///< free flight's real collision
    double T = 1.0;           ///< the current shadow walk's estimate
    bool hit = false;
    Phase phase = Phase::Ended;
  };

  /// A path between calls. Trivially copyable.
  struct State {
    typename Tracer::PathState path = Tracer::begin(Ray{Vec3(0.0), Vec3(0.0, 0.0, 1.0)});
    typename Tracer::Scatter scatter;
    typename Tracer::LightPending light;
    Walk w;
    Ray last_ray{Vec3(0.0), Vec3(0.0, 0.0, 1.0)};  ///< the last bounce's sampled direction
    double last_pdf = 0.0;                         ///< its solid-angle pdf
    double T_last = 1.0;                           ///< the last bounce's transmittance up to t_prev
    double t_prev = 0.0;                           ///< the last bounce's emitter reached so far
    int last = -1;                                 ///< ... and its index (-1: none yet)
    int target = -1;  ///< the area light the last bounce's walk goes to (-1: the infinite lights)
  };

  /// The path of a camera ray, before its first free flight.
  TESSERA_HOST_DEVICE static State begin(const Ray& ray) {
    State s;
    s.path = Tracer::begin(ray);
    s.w.phase = Phase::StartFlight;
    return s;
  }

  /// True while path s is in a walk: its next piece is a tracking step (step()); else the
  /// code between walks (between()), or nothing once it has ended.
  TESSERA_HOST_DEVICE static bool walking(const State& s) { return walking(s.w); }
  TESSERA_HOST_DEVICE static bool walking(const Walk& w) {
    return w.phase == Phase::Flight || w.phase == Phase::Shadow || w.phase == Phase::LastShadow;
  }

  /// Advances path s by one tracking step (see above); false once it has ended (s.path.out is
  /// then its sample). A walk that needs no step (a ray through empty cells only) ends
  /// without one; the biased fixed-step march (FreePath::Raymarch) is not resumable and runs
  /// whole in the call that starts the flight. advance = between (when not walking), step,
  /// and between again when the step ended its walk.
  TESSERA_HOST_DEVICE static bool advance(const Tracer& t, State& s, Rng& rng, KernelCounters& k,
                                          const SobolSampler* ld) {
    for (bool stepped = false;;) {  // (one call site of each half: the device's code stays small)
      if (walking(s)) {
        if (stepped) return true;
        stepped = true;
        if (step(t, s.w, rng, k)) return true;
      }
      if (!between(t, s, rng, k, ld)) return false;
    }
  }

  /// One tracking step of a path's walk w (walking(w)); true while the walk goes on. When it
  /// ends, the path is between walks (between() next). Reads and writes w and rng only.
  TESSERA_HOST_DEVICE static bool step(const Tracer& t, Walk& w, Rng& rng, KernelCounters& k) {
    const TrackStep r = w.steps.next(rng);
    if (w.phase == Phase::Flight) {
      w.phase = Phase::Collide;
      if (r == TrackStep::Collision) {
        if (!t.flight_step(w.steps.position(), w.steps.majorant(), rng, k)) {
          w.phase = Phase::Flight;  // a null collision: the walk goes on
          return true;
        }
        w.hit = true;
        w.t_hit = w.steps.t();
      } else if (r == TrackStep::Stalled) {
        ++k.stalled_paths;  // a loop guard ended the path: nothing more from it
        w.phase = Phase::Ended;
      }
      return false;
    }
    if (r == TrackStep::Collision && t.shadow_update(w.steps.position(), w.steps.majorant(), rng, k, w.T)) return true;
    w.T = Tracer::shadow_end(r == TrackStep::Stalled, w.T, k);
    w.phase = w.phase == Phase::Shadow ? Phase::Lit : Phase::LastLit;
    return false;
  }

  /// The code of s's bounce between walks, up to the start of its next walk (true: walking(s))
  /// or the path's end (false).
  TESSERA_HOST_DEVICE static bool between(const Tracer& t, State& s, Rng& rng, KernelCounters& k,
                                          const SobolSampler* ld) {
    using Next = typename Tracer::Next;
    using Span = typename Tracer::Span;
    const LightSet& L = t.lights();
    for (;;) {
      switch (s.w.phase) {
        case Phase::Flight:
        case Phase::Shadow:
        case Phase::LastShadow: return true;
        case Phase::Ended: return false;
        case Phase::StartFlight: {
          Span sp;
          s.w.t_hit = INFINITY;
          s.w.hit = false;
          s.w.phase = Phase::Collide;
          switch (t.flight_begin(s.path.ray, rng, k, &sp, &s.w.t_hit)) {
            case Tracer::FlightStart::Miss: break;
            case Tracer::FlightStart::Hit: s.w.hit = true; break;
            case Tracer::FlightStart::Stalled: s.w.phase = Phase::Ended; break;
            case Tracer::FlightStart::Walk:
              s.w.steps = t.walk(sp);
              s.w.phase = Phase::Flight;
              break;
          }
          break;
        }
        case Phase::Collide: {
          s.w.phase = Phase::Ended;
          if (!t.collide(s.path, s.w.hit, s.w.t_hit, rng, k, ld, s.scatter)) break;
          s.w.phase = Phase::Scatter;
          if (L.count() == 0) break;
          if (!t.sample_light(s.scatter, s.path.ray.d, s.scatter.first ? ld : nullptr, rng, s.light)) {
            s.path.out.L += s.path.beta * Color(0.0);  // as bounce adds a light sample that adds nothing
            break;
          }
          shadow_walk_to(t, s, s.light.shadow, 0.0, s.light.dist, k, Phase::Shadow, Phase::Lit);
          break;
        }
        case Phase::Lit:
          s.path.out.L += s.path.beta * Tracer::light_arrived(s.light, s.w.T);
          s.w.phase = Phase::Scatter;
          break;
        case Phase::Scatter: {
          const Next r = t.scatter(s.path, s.scatter, ld, rng, &s.last_ray, &s.last_pdf);
          s.w.phase = Phase::Ended;
          if (r == Next::Continue) s.w.phase = Phase::StartFlight;
          else if (r == Next::Last && L.count() > 0) {
            s.T_last = 1.0;
            s.t_prev = 0.0;
            s.last = -1;
            s.w.phase = Phase::Gather;
          }
          break;
        }
        case Phase::Gather: {
          // The next area light along the ray while light gets through, then the infinite
          // lights behind everything (gather_with_transmittance)
          const Ray& ray = s.last_ray;
          s.target = s.T_last > 0.0 ? t.next_light(s.t_prev, s.last, [&](int i) { return L[i].intersect(ray); }) : -1;
          double tb = INFINITY;
          if (s.target >= 0) tb = L[s.target].intersect(ray);
          else if (!(L.area_count() < L.count() && s.T_last > 0.0)) {
            s.w.phase = Phase::Ended;
            break;
          }
          shadow_walk_to(t, s, ray, s.t_prev, tb, k, Phase::LastShadow, Phase::LastLit);
          break;
        }
        case Phase::LastLit: {
          s.T_last *= s.w.T;
          if (s.target < 0) {
            if (s.T_last > 0.0) t.add_infinite_lights(s.last_ray, s.T_last, s.last_pdf, s.path.beta, s.path.out.L);
            s.w.phase = Phase::Ended;
            break;
          }
          s.t_prev = L[s.target].intersect(s.last_ray);
          s.last = s.target;
          if (s.T_last > 0.0)
            t.add_area_light(s.target, s.last_ray, s.t_prev, s.T_last, s.last_pdf, s.path.beta, s.path.out.L);
          s.w.phase = Phase::Gather;
          break;
        }
      }
    }
  }

 private:
  /// A transmittance estimate along `ray` over [ta, tb]: its walk (phase `walk_phase`) or, when
  /// it needs none, its value at once (phase `known`).
  TESSERA_HOST_DEVICE static void shadow_walk_to(const Tracer& t, State& s, const Ray& ray, double ta, double tb,
                                                 KernelCounters& k, Phase walk_phase, Phase known) {
    typename Tracer::Span sp;
    const double v = t.shadow_begin(ray, ta, tb, k, &sp);
    if (v >= 0.0) {
      s.w.T = v;
      s.w.phase = known;
      return;
    }
    s.w.T = 1.0;
    s.w.steps = t.walk(sp);
    s.w.phase = walk_phase;
  }
};

}  // namespace tessera
