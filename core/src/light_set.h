#pragma once
/// The light set the kernels see: lights of every kind in one array, behind intersect /
/// radiance / pdf / sample by index, and the light-selection strategy as its own small type.
/// The integrator (path_tracer.h) names no concrete light type; adding a light kind means a
/// new Light::Kind with its cases below, its prepared class (area_lights.h style) and the
/// loop in make_lights that appends it, plus its parser on the config side.
///
/// Order of the array (kept so that images stay bit-identical): rect lights, sphere lights,
/// then the infinite lights (the background, when it emits). Area lights come first and are
/// the ones a ray can meet at a finite distance: indices [0, area_count()).
#include <tessera/scene.h>

#include "area_lights.h"
#include "environment.h"

#include <algorithm>
#include <type_traits>
#include <vector>

namespace tessera {

/// Most lights a scene may hold: area lights (prepare checks) plus the background.
inline constexpr int kMaxLights = 64;

/// One prepared light of any kind. Trivially copyable; the environment kind points to the
/// prepared scene's Environment (owned there, valid while it lives).
class Light {
 public:
  enum class Kind { Rect, Sphere, Environment };

  static Light rect(const RectLightDesc& d) { Light l(Kind::Rect); l.m_rect = RectLight(d); return l; }
  static Light sphere(const SphereLightDesc& d) { Light l(Kind::Sphere); l.m_sphere = SphereLight(d); return l; }
  static Light environment(const Environment* env) { Light l(Kind::Environment); l.m_env = env; return l; }

  /// True for a light at infinity (met only by rays that leave the scene).
  bool infinite() const { return m_kind == Kind::Environment; }

  /// Distance in (0, inf) along r to the light's emitting side, or -1 (always for infinite lights).
  double intersect(const Ray& r) const {
    switch (m_kind) {
      case Kind::Rect: return m_rect.intersect_front(r);
      case Kind::Sphere: return m_sphere.intersect_front(r);
      default: return -1.0;
    }
  }
  /// Radiance arriving along -d from the point of this light that direction d meets.
  Color radiance(const Vec3& d) const {
    switch (m_kind) {
      case Kind::Rect: return m_rect.radiance();
      case Kind::Sphere: return m_sphere.radiance();
      default: return m_env->eval(d);
    }
  }
  /// Solid-angle pdf that sample(x, ...) returns wi, which meets the light at distance t
  /// (ignored by infinite lights).
  double pdf(const Vec3& x, const Vec3& wi, double t) const {
    switch (m_kind) {
      case Kind::Rect: return m_rect.pdf(x, wi, t);
      case Kind::Sphere: return m_sphere.pdf(x, wi, t);
      default: return m_env->pdf(wi);
    }
  }
  /// A direction toward the light from x for (u1, u2) in [0, 1)^2; pdf 0 = failed. Infinite
  /// lights return dist = inf.
  LightSample sample(const Vec3& x, double u1, double u2) const {
    switch (m_kind) {
      case Kind::Rect: return m_rect.sample(x, u1, u2);
      case Kind::Sphere: return m_sphere.sample(x, u1, u2);
      default: {
        double pdf;
        Vec3 wi;
        const Color Le = m_env->sample(u1, u2, &wi, &pdf);
        return LightSample{wi, INFINITY, Le, pdf};
      }
    }
  }
  /// World box around a finite light (for image-space culling); not called for infinite ones.
  void bounds(Vec3* lo, Vec3* hi) const {
    if (m_kind == Kind::Rect) m_rect.bounds(lo, hi);
    else m_sphere.bounds(lo, hi);
  }

 private:
  explicit Light(Kind k) : m_kind(k) {}
  Kind m_kind;
  RectLight m_rect;
  SphereLight m_sphere;
  const Environment* m_env = nullptr;
};
static_assert(std::is_trivially_copyable_v<Light>);

/// Light selection for next-event estimation: uniform over the lights. Power-based selection
/// would replace this type (pick and pmf) and nothing else.
class UniformLightSampler {
 public:
  UniformLightSampler() = default;
  explicit UniformLightSampler(int count) : m_n(count) {}
  /// Index for u in [0, 1); count() > 0.
  int pick(double u) const { return std::min(m_n - 1, static_cast<int>(u * m_n)); }
  /// Probability that pick() returns i (the same for every i); 0 when there is no light.
  double pmf(int) const { return m_n > 0 ? 1.0 / m_n : 0.0; }

 private:
  int m_n = 0;
};
using LightSampler = UniformLightSampler;

/// The view the kernels take: the prepared lights (owned by the prepared scene), the
/// selection strategy and the background as camera rays see it. Trivially copyable.
class LightSet {
 public:
  LightSet() = default;
  LightSet(const Light* lights, int count, const Environment* background)
      : m_lights(lights), m_count(count), m_sampler(count), m_background(background) {
    m_area = static_cast<int>(std::find_if(lights, lights + count, [](const Light& l) { return l.infinite(); }) - lights);
  }
  int count() const { return m_count; }
  int area_count() const { return m_area; }   ///< lights [0, area_count()) are finite
  const Light& operator[](int i) const { return m_lights[i]; }
  const LightSampler& sampler() const { return m_sampler; }
  /// The background seen by camera rays that escape: shown unless hidden (visible: false),
  /// whether or not it lights the scene.
  bool background_visible() const { return m_background->visible(); }
  Color background(const Vec3& d) const { return m_background->eval(d); }

 private:
  const Light* m_lights = nullptr;
  int m_count = 0, m_area = 0;
  LightSampler m_sampler;
  const Environment* m_background = nullptr;
};
static_assert(std::is_trivially_copyable_v<LightSet>);

/// Every light of the scene in the set's order (rects, spheres, then the background when it
/// emits). `env` must outlive the result.
inline std::vector<Light> make_lights(const SceneDesc& s, const Environment* env) {
  std::vector<Light> out;
  for (const RectLightDesc& l : s.rect_lights) out.push_back(Light::rect(l));
  for (const SphereLightDesc& l : s.sphere_lights) out.push_back(Light::sphere(l));
  if (env->emits()) out.push_back(Light::environment(env));
  return out;
}

}  // namespace tessera
