// Points (`[x, y, z]`, `center`, `{orbit: ...}`) and lengths (a number or `{relative: r}`).
#include <tessera/config/point_spec.h>

#include "parsers.h"

#include <cmath>
#include <cstdlib>
#include <string>

namespace tessera::config::detail {

namespace {
// The keys of the mappings a point or a length may be, each with what it takes:
// `{orbit: {azimuth: degrees, elevation: degrees, distance: radii}}` and `{relative: r}`
// (each orbit value may also be `{start: S, per_step: D}`, kMovingKeys)
constexpr KeyShape kOrbitKeys[] = {{"azimuth", "degrees"}, {"elevation", "degrees"}, {"distance", "radii"}};
const std::string kOrbitNames = braced(kOrbitKeys, true);
const KeyShape kPointKeys[] = {{"orbit", kOrbitNames}};
constexpr KeyShape kLengthKeys[] = {{"relative", "r"}};
// An orbit value that moves: `{start: S, per_step: D}`, S + D * n at simulation step n
constexpr KeyShape kMovingKeys[] = {{"start", "S"}, {"per_step", "D"}};

// Whether a scalar's text starts like a number (so a word such as `fitt` gets the message that
// lists `fit`, and a number gets Value::number's range check)
bool reads_as_number(const std::string& text) {
  char* end = nullptr;
  std::strtod(text.c_str(), &end);
  return end != text.c_str();
}

// One orbit value: a number in `r`, or `{start: S, per_step: D}` with S in `r` and
// |D| <= kMaxPerStep (build_scene checks S + D * n against `r` at each step); `distance`:
// the value is the orbit's distance, where `start: fit` gets its own message
OrbitValue parse_orbit_value(const Value& v, const Range& r, bool distance = false) {
  const std::string start_allowed =
      std::isfinite(r.lo) || std::isfinite(r.hi) ? "a number in " + r.describe() : std::string("a finite number");
  if (v.is_sequence())
    v.fail(v.describe() + " is not allowed here (allowed: " + start_allowed + ", or " + braced(kMovingKeys) +
           ", S + D * n at simulation step n)");
  if (!v.is_map()) return v.number(r);
  const Map m = v.map(braced(kMovingKeys));
  m.allow(kMovingKeys);
  const std::string per_step_allowed = "a number in [-" + format_number(kMaxPerStep) + ", " +
                                       format_number(kMaxPerStep) + "], the change per simulation step";
  const Value start = m.require("start", start_allowed + ", the value at step 0");
  // `fit` is computed from the view, not from the step: it does not move
  if (distance && start.is_word("fit"))
    start.fail("distance: fit cannot move per step (allowed: distance: fit, or {start: S, per_step: D} with S a "
               "number >= 0, in bounding-sphere radii of the data)");
  const double s = start.number(r);
  return {s, m.require("per_step", per_step_allowed).number(Range::closed(-kMaxPerStep, kMaxPerStep))};
}
}  // namespace

std::string point_allowed() { return "[x, y, z], center or " + braced(kPointKeys); }

std::string length_map_allowed() { return braced(kLengthKeys); }

bool plainly_same(const PointSpec& a, const PointSpec& b) {
  if (a.kind != b.kind) return false;
  return a.kind == PointSpec::Kind::Center || (a.kind == PointSpec::Kind::Absolute && a.xyz == b.xyz);
}

PointSpec parse_point(const Value& v, bool allow_fit) {
  if (v.is_word("center")) return PointSpec::center();
  if (v.is_sequence()) return PointSpec::absolute(v.vec3());
  const std::string allowed = point_allowed();
  if (v.is_scalar()) v.fail(v.describe() + " is not a point (allowed: " + allowed + ")");

  const Map m = v.map(allowed);
  m.allow(kPointKeys);
  const Value o = m.require("orbit", allowed);
  const Map om = o.map(braced(kOrbitKeys));
  om.allow(kOrbitKeys);
  OrbitSpec s;
  if (const auto a = om.get("azimuth")) s.azimuth = parse_orbit_value(*a, Range::any());
  if (const auto e = om.get("elevation"))
    s.elevation = parse_orbit_value(*e, Range::closed(kMinElevation, kMaxElevation));
  const char* distance_allowed = allow_fit ? "a number >= 0, in bounding-sphere radii of the data, "
                                             "{start: S, per_step: D} or fit"
                                           : "a number >= 0, in bounding-sphere radii of the data, or "
                                             "{start: S, per_step: D}";
  const Value d = om.require("distance", distance_allowed);
  if (d.is_word("fit")) {
    if (!allow_fit)
      d.fail("distance: fit frames the data in the camera's view, so only camera.position takes it "
             "(allowed here: a number >= 0, in bounding-sphere radii of the data)");
    return PointSpec::on_orbit_fit(s.azimuth, s.elevation);
  }
  if (allow_fit && d.is_scalar() && !reads_as_number(std::string(d.text())))
    d.fail(d.describe() + " is not a distance (allowed: " + std::string(distance_allowed) + ")");
  s.distance = parse_orbit_value(d, Range::at_least(kMinDistance), true);
  return PointSpec::on_orbit(s.azimuth, s.elevation, s.distance);
}

LengthSpec parse_length(const Value& v, bool strictly_positive) {
  const Range r = strictly_positive ? Range::above(0.0) : Range::at_least(0.0);
  if (v.is_scalar()) return LengthSpec::world(v.number(r));
  const Map m =
      v.map("a number in world units or " + length_map_allowed() + " (r times the data's bounding-sphere radius)");
  m.allow(kLengthKeys);
  return LengthSpec::relative_to_radius(
      m.require("relative", "a multiple of the data's bounding-sphere radius").number(r));
}

}  // namespace tessera::config::detail
