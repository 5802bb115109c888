#pragma once
/// What every light kind provides (the kernel-side interface) and the light sample it returns.
/// Each kind lives in its own file (rect_light.h, sphere_light.h) with its description's
/// checks for prepare() and its prepared class; area_lights.h lists those files.
#include <tessera/lights.h>
#include <tessera/math.h>

#include <string>

namespace tessera {

struct LightSample {
  Vec3 wi;      ///< unit direction from the shading point to the light point
  double dist;  ///< distance to the light point
  Color L;      ///< radiance arriving along -wi (0 if the back side was sampled)
  double pdf;   ///< solid-angle pdf of wi under this light's strategy
};

/// LightKind<Desc>, specialised once per alternative of LightDesc (lights.h) in that kind's
/// file, names the kind's prepared class and checks its description:
///   using Kernel = ...;   trivially copyable; Kernel(const Desc&) may throw
///                         std::invalid_argument; offers kInfinite (false), intersect_front(ray)
///                         (distance in (0, inf) to the emitting side, or -1), radiance(d),
///                         pdf(x, wi, t), sample(x, u1, u2) and bounds(lo, hi) (a world box).
///   static constexpr const char* kName;   "rect light": errors say "<kName> <i>", i counted
///                                         per kind in list order
///   template <class Check> static void validate(const Desc&, const Check& c);
///       calls c.point(key, p) for every point, c.length(key, v) for every length and
///       c.radiance(L) (prepare()'s scale checks; they throw naming the light and key).
template <class Desc>
struct LightKind;

}  // namespace tessera
