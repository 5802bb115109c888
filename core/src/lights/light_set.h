#pragma once
/// The light set the kernels see: lights of every kind in one array, behind intersect /
/// radiance / pdf / sample by index, and the light-selection strategy as its own small type.
/// The integrator (path_tracer.h) names no concrete light type.
///
/// Order of the array (kept so that images stay bit-identical): the area lights kind by kind
/// in the order of LightDesc's alternatives (rect lights, then sphere lights), each kind in
/// list order, then the infinite lights (the background, when it emits). Area lights are the
/// ones a ray can meet at a finite distance: indices [0, area_count()).
///
/// Light and make_lights follow LightDesc (lights.h) generically: a new kind needs nothing
/// here (its file and LightDesc entry, docs/lights.md).
#include <tessera/scene.h>

#include "lights/area_lights.h"
#include "lights/environment.h"

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace tessera {

/// Most lights a scene may hold: area lights (prepare checks) plus the background.
inline constexpr int kMaxLights = 64;

/// The background as a light: the interface of the area lights over the prepared scene's
/// Environment (owned there). Infinite: met only by rays that leave the scene.
class EnvironmentLight {
 public:
  static constexpr bool kInfinite = true;
  explicit EnvironmentLight(const Environment* env) : m_env(env) {}
  TESSERA_HOST_DEVICE double intersect_front(const Ray&) const { return -1.0; }
  TESSERA_HOST_DEVICE Color radiance(const Vec3& d) const { return m_env->eval(d); }
  TESSERA_HOST_DEVICE double pdf(const Vec3&, const Vec3& wi, double) const { return m_env->pdf(wi); }
  TESSERA_HOST_DEVICE LightSample sample(const Vec3&, double u1, double u2) const {
    double pdf;
    Vec3 wi;
    const Color Le = m_env->sample(u1, u2, &wi, &pdf);
    return LightSample{wi, INFINITY, Le, pdf};
  }

 private:
  const Environment* m_env;
};

namespace detail {
template <class V>
struct KernelLights;
template <class... D>
struct KernelLights<std::variant<D...>> {
  using type = std::variant<typename LightKind<D>::Kernel..., EnvironmentLight>;
};
}  // namespace detail

/// The prepared light kinds: one per alternative of LightDesc, in its order, then the
/// background. Derived from LightDesc, so the two cannot disagree.
using KernelLight = detail::KernelLights<LightDesc>::type;
static_assert(std::variant_size_v<KernelLight> == std::variant_size_v<LightDesc> + 1);

namespace detail {
/// fn(the alternative v holds): an if-chain over the alternatives (no std::visit, so no
/// exception path in the kernels; v is never valueless, every alternative being trivially
/// copyable).
template <std::size_t I, class V, class Fn>
TESSERA_HOST_DEVICE decltype(auto) dispatch_light(const V& v, Fn& fn) {
  if constexpr (I + 1 == std::variant_size_v<V>) {
    return fn(*std::get_if<I>(&v));
  } else {
    if (v.index() == I) return fn(*std::get_if<I>(&v));
    return dispatch_light<I + 1>(v, fn);
  }
}
}  // namespace detail

/// One prepared light of any kind, by value (trivially copyable). Every kind K offers
/// kInfinite, intersect_front(ray) (distance in (0, inf) to its emitting side, or -1),
/// radiance(d), pdf(x, wi, t), sample(x, u1, u2) and, when finite, bounds(lo, hi); the
/// methods here dispatch on the kind once, in dispatch().
class Light {
 public:
  template <class K, class = std::enable_if_t<!std::is_same_v<std::decay_t<K>, Light>>>
  explicit Light(const K& l) : m_v(std::in_place_type<K>, l) {}

  /// fn(the concrete light); every instantiation returns the same type.
  template <class Fn>
  TESSERA_HOST_DEVICE decltype(auto) dispatch(Fn&& fn) const {
    return detail::dispatch_light<0>(m_v, fn);
  }

  /// True for a light at infinity (met only by rays that leave the scene).
  TESSERA_HOST_DEVICE bool infinite() const {
    return dispatch([](const auto& l) { return std::decay_t<decltype(l)>::kInfinite; });
  }
  /// Distance in (0, inf) along r to the light's emitting side, or -1 (always for infinite lights).
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE double intersect(const Ray& r) const {
    return dispatch([&](const auto& l) { return l.intersect_front(r); });
  }
  /// Radiance arriving along -d from the point of this light that direction d meets.
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE Color radiance(const Vec3& d) const {
    return dispatch([&](const auto& l) { return l.radiance(d); });
  }
  /// Solid-angle pdf that sample(x, ...) returns wi, which meets the light at distance t
  /// (ignored by infinite lights).
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE double pdf(const Vec3& x, const Vec3& wi, double t) const {
    return dispatch([&](const auto& l) { return l.pdf(x, wi, t); });
  }
  /// A direction toward the light from x for (u1, u2) in [0, 1)^2; pdf 0 = failed. Infinite
  /// lights return dist = inf.
  TESSERA_HOST_DEVICE TESSERA_DEVICE_NOINLINE LightSample sample(const Vec3& x, double u1, double u2) const {
    return dispatch([&](const auto& l) { return l.sample(x, u1, u2); });
  }
  /// World box around a finite light (image-space culling); an infinite one leaves lo, hi.
  void bounds(Vec3* lo, Vec3* hi) const {
    dispatch([&](const auto& l) {
      if constexpr (!std::decay_t<decltype(l)>::kInfinite) l.bounds(lo, hi);
    });
  }

 private:
  KernelLight m_v;
};
static_assert(std::is_trivially_copyable_v<Light>);

/// Light selection for next-event estimation: uniform over the lights. Power-based selection
/// would replace this type (pick and pmf) and nothing else.
class UniformLightSampler {
 public:
  UniformLightSampler() = default;
  explicit UniformLightSampler(int count) : m_n(count) {}
  /// Index for u in [0, 1); count() > 0.
  TESSERA_HOST_DEVICE int pick(double u) const { return std::min(m_n - 1, static_cast<int>(u * m_n)); }
  /// Probability that pick() returns i (the same for every i); 0 when there is no light.
  TESSERA_HOST_DEVICE double pmf(int) const { return m_n > 0 ? 1.0 / m_n : 0.0; }

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
    m_area =
        static_cast<int>(std::find_if(lights, lights + count, [](const Light& l) { return l.infinite(); }) - lights);
  }
  TESSERA_HOST_DEVICE int count() const { return m_count; }
  TESSERA_HOST_DEVICE int area_count() const { return m_area; }  ///< lights [0, area_count()) are finite
  TESSERA_HOST_DEVICE const Light& operator[](int i) const { return m_lights[i]; }
  TESSERA_HOST_DEVICE const LightSampler& sampler() const { return m_sampler; }
  /// The background seen by camera rays that escape: shown unless hidden (visible: false),
  /// whether or not it lights the scene.
  TESSERA_HOST_DEVICE bool background_visible() const { return m_background->visible(); }
  TESSERA_HOST_DEVICE Color background(const Vec3& d) const { return m_background->eval(d); }
  /// This set over copies of its lights and background elsewhere (a device's memory):
  /// the same count, order and sampler, other addresses.
  LightSet relocated(const Light* lights, const Environment* background) const {
    LightSet s = *this;
    s.m_lights = lights;
    s.m_background = background;
    return s;
  }

 private:
  const Light* m_lights = nullptr;
  int m_count = 0, m_area = 0;
  LightSampler m_sampler;
  const Environment* m_background = nullptr;
};
static_assert(std::is_trivially_copyable_v<LightSet>);

namespace detail {
template <std::size_t I>
void append_kind(const std::vector<LightDesc>& lights, std::vector<Light>* out) {
  using Desc = std::variant_alternative_t<I, LightDesc>;
  for (const LightDesc& l : lights)
    if (const Desc* d = std::get_if<Desc>(&l)) out->emplace_back(typename LightKind<Desc>::Kernel(*d));
}
template <std::size_t... I>
void append_kinds(const std::vector<LightDesc>& lights, std::vector<Light>* out, std::index_sequence<I...>) {
  (append_kind<I>(lights, out), ...);
}
}  // namespace detail

/// Every light of the scene in the set's order (kind by kind in LightDesc's order, each kind
/// in list order, then the background when it emits). `env` must outlive the result.
inline std::vector<Light> make_lights(const SceneDesc& s, const Environment* env) {
  std::vector<Light> out;
  detail::append_kinds(s.lights, &out, std::make_index_sequence<std::variant_size_v<LightDesc>>{});
  if (env->emits()) out.emplace_back(EnvironmentLight(env));
  return out;
}

}  // namespace tessera
