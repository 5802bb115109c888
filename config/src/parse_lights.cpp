// `lights:` (rect and sphere area lights) and `background:`.
#include <tessera/config/light_spec.h>

#include "enum_names.h"
#include "parsers.h"

#include <string>
#include <variant>
#include <vector>

namespace tessera::config::detail {
namespace {

const Range kNonNegative = Range::at_least(0.0);

/// `size: [w, h]`, `size: w` (a square) or `size: {relative: r}`; each length > 0.
void parse_rect_size(const Value& v, RectLightSpec& l) {
  if (v.is_sequence()) {
    const auto wh = v.list("[width, height], each a number or " + length_map_allowed(), 2, 2);
    l.width = parse_length(wh[0], true);
    l.height = parse_length(wh[1], true);
  } else {
    l.width = l.height = parse_length(v, true);
  }
}

/// `color` and `intensity`, which every kind has.
template <class Spec>
void parse_emission(const Map& m, Spec& l) {
  l.color = m.color_or("color", l.color, kNonNegative);
  l.intensity = m.number_or("intensity", l.intensity, kNonNegative);
}

// Each kind's keys, one overload per alternative of LightSpec (parse_light visits them)

void parse_keys(const Map& m, RectLightSpec& l) {
  m.allow({"type", "position", "target", "size", "color", "intensity"});
  l.position = parse_point(m.require("position", point_allowed()));
  if (const auto t = m.get("target")) l.target = parse_point(*t);
  if (const auto s = m.get("size")) parse_rect_size(*s, l);
  parse_emission(m, l);

  // A rect light aimed at itself has no facing
  if (plainly_same(l.position, l.target))
    m.get("position")->fail("light position equals its target (allowed: a point other than target)");
}

void parse_keys(const Map& m, SphereLightSpec& l) {
  m.allow({"type", "position", "radius", "color", "intensity"});
  l.position = parse_point(m.require("position", point_allowed()));
  if (const auto r = m.get("radius")) l.radius = parse_length(*r, true);
  parse_emission(m, l);
}

}  // namespace

LightSpec parse_light(const Value& v) {
  const std::vector<std::string> types = names_of(kLightTypeNames);
  const Map m = v.map("a mapping {type: " + join_words(types, " | ", " | ") + ", ...}");
  // The named kind's spec with its defaults, then its keys
  LightSpec l = m.require("type", join_words(types)).choice(kLightTypeNames);
  std::visit([&m](auto& kind) { parse_keys(m, kind); }, l);
  return l;
}

BackgroundSpec parse_background(const Value& v) {
  const std::vector<std::string> types = names_of(kBackgroundTypeNames);
  const Map m = v.map("a mapping {type: " + join_words(types, " | ", " | ") + ", ...}");
  BackgroundSpec b;
  b.type = m.require("type", join_words(types)).choice(kBackgroundTypeNames);
  switch (b.type) {
    case BackgroundType::Constant:
      m.allow({"type", "color", "intensity", "visible"});
      b.color = m.color_or("color", b.color, kNonNegative);
      break;
    case BackgroundType::Gradient:
      m.allow({"type", "top", "middle", "bottom", "up", "intensity", "visible"});
      b.top = m.color_or("top", b.top, kNonNegative);
      b.middle = m.color_or("middle", b.middle, kNonNegative);
      b.bottom = m.color_or("bottom", b.bottom, kNonNegative);
      break;
    case BackgroundType::EnvMap:
      m.allow({"type", "file", "up", "intensity", "visible"});
      b.file = resolve_existing_file(m.require("file", "an EXR file, relative to this YAML file"));
      break;
  }
  if (const auto u = m.get("up")) {
    b.up = u->vec3();
    if (b.up == Vec3(0.0)) u->fail("[0, 0, 0] has no direction (allowed: a non-zero vector)");
  }
  b.intensity = m.number_or("intensity", b.intensity, kNonNegative);
  b.visible = m.boolean_or("visible", b.visible);
  return b;
}

}  // namespace tessera::config::detail
