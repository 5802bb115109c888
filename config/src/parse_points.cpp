// Points (`[x, y, z]`, `center`, `{orbit: ...}`) and lengths (a number or `{relative: r}`).
#include <tessera/config/point_spec.h>

#include "parsers.h"

namespace tessera::config::detail {

namespace {
constexpr const char* kPointAllowed = "[x, y, z], center or {orbit: {azimuth, elevation, distance}}";
}

PointSpec parse_point(const Value& v) {
  if (v.is_word("center")) return PointSpec::center();
  if (v.is_sequence()) return PointSpec::absolute(v.vec3());
  if (v.is_scalar()) v.fail(v.describe() + " is not a point (allowed: " + std::string(kPointAllowed) + ")");

  const Map m = v.map(kPointAllowed);
  m.allow({"orbit"});
  const Value o = m.require("orbit", kPointAllowed);
  const Map om = o.map("{azimuth: degrees, elevation: degrees, distance: radii}");
  om.allow({"azimuth", "elevation", "distance"});
  OrbitSpec s;
  s.azimuth = om.number_or("azimuth", 0.0);
  s.elevation = om.number_or("elevation", 0.0, Range::closed(-90.0, 90.0));
  s.distance = om.require("distance", "a number >= 0, in bounding-sphere radii of the data")
                   .number(Range::at_least(0.0));
  return PointSpec::on_orbit(s.azimuth, s.elevation, s.distance);
}

LengthSpec parse_length(const Value& v, bool strictly_positive) {
  const Range r = strictly_positive ? Range::above(0.0) : Range::at_least(0.0);
  if (v.is_scalar()) return LengthSpec::world(v.number(r));
  const Map m = v.map("a number in world units or {relative: r} (r times the data's "
                      "bounding-sphere radius)");
  m.allow({"relative"});
  return LengthSpec::relative_to_radius(
      m.require("relative", "a multiple of the data's bounding-sphere radius").number(r));
}

}  // namespace tessera::config::detail
