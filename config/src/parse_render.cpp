// One entry of `renders:`: name, field, trigger, image, camera, output (the larger blocks,
// transfer function, lights, background and integrator, have files of their own), and which
// of the defaults of render_defaults.h a render that leaves blocks out takes.
#include <tessera/config/output_path.h>
#include <tessera/config/render_defaults.h>
#include <tessera/config/render_spec.h>
#include <tessera/image_format.h>

#include "enum_names.h"
#include "parsers.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::config {
using detail::Map;
using detail::Range;
using detail::Value;

namespace {

constexpr std::int64_t kMaxImageEdge = ImageDesc::kMaxEdge;
/// Field names are echoed in messages and compared with what the simulation publishes.
constexpr std::size_t kMaxFieldName = 256;

/// Render names end up in file names ({name}), log lines and every message about the render.
constexpr std::size_t kMaxRenderName = RenderSpec::kMaxName;

bool valid_name(const std::string& s) {
  return !s.empty() && s.size() <= kMaxRenderName && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

/// `image:` into r.image and r.min_spp (which must not pass spp).
void parse_image(const Value& v, RenderSpec& r) {
  const Map m = v.map_with_keys({"width", "height", "spp", "min_spp", "target_error", "denoise"});
  ImageDesc& d = r.image;
  d.width = static_cast<int>(m.integer_or("width", d.width, 1, kMaxImageEdge));
  d.height = static_cast<int>(m.integer_or("height", d.height, 1, kMaxImageEdge));
  d.spp = static_cast<int>(m.integer_or("spp", d.spp, 1, ImageDesc::kMaxSpp));
  d.target_error = m.number_or("target_error", d.target_error, Range::at_least(0.0));
  d.denoise = m.boolean_or("denoise", d.denoise);
  if (const auto lo = m.get("min_spp")) {
    r.min_spp = static_cast<int>(lo->integer(1, ImageDesc::kMaxSpp));
    if (r.min_spp > d.spp)
      lo->fail("image.min_spp " + std::to_string(r.min_spp) + " is more than image.spp " + std::to_string(d.spp) +
               " (allowed: 1 <= min_spp <= spp; with a budget spp is the most a pixel gets, min_spp the fewest)");
  }
}

/// The shared keys of a camera (`up`, `aperture`, `focus_distance`) into c.
void parse_camera_common(const Map& m, CameraSpec& c) {
  if (const auto u = m.get("up")) {
    c.up = u->vec3();
    if (c.up == Vec3(0.0)) u->fail("[0, 0, 0] has no direction (allowed: a non-zero vector)");
  }
  c.aperture = m.number_or("aperture", c.aperture, Range::at_least(0.0));
  c.focus_distance = m.number_or("focus_distance", c.focus_distance, Range::at_least(0.0));
}

/// A keyframe's point: as anywhere else, but it does not move per step (the keyframes do).
PointSpec parse_keyframe_point(const Value& v, bool allow_fit) {
  const PointSpec p = detail::parse_point(v, allow_fit);
  if (p.moves())
    v.fail("a keyframe's orbit does not move per step: the keyframes move the camera (allowed: plain numbers for "
           "azimuth, elevation and distance, not {start, per_step})");
  return p;
}

/// `camera: {keyframes: [...], interpolation, up, aperture, focus_distance}` into c.
void parse_keyframes(const Map& m, const Value& list, CameraSpec& c) {
  // position, look_at and fov belong to each keyframe
  for (const char* own : {"position", "look_at", "fov"})
    if (const auto o = m.get(own))
      o->fail(std::string("camera.") + own + " beside camera.keyframes (allowed: either position, look_at and fov, " +
              "or keyframes, each keyframe with its own position, look_at and fov)");
  parse_camera_common(m, c);
  c.interpolation = m.choice_or("interpolation", c.interpolation, detail::kCameraInterpolationNames);
  const std::string each = "{step: N, position: point, look_at: point, fov: degrees}";
  for (const Value& e :
       list.list("a list of keyframes, each " + each + ", in increasing step order", 1, CameraSpec::kMaxKeyframes)) {
    const Map km = e.map_with_keys({"step", "position", "look_at", "fov"}, " (a keyframe: " + each + ")");
    CameraKeyframe k;
    const Value step = km.require("step", "an integer, the simulation step of this keyframe");
    k.step = step.integer(std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max());
    if (!c.keyframes.empty() && k.step <= c.keyframes.back().step)
      step.fail("keyframe step " + std::to_string(k.step) +
                (k.step == c.keyframes.back().step ? " is given twice"
                                                   : " comes after step " + std::to_string(c.keyframes.back().step)) +
                " (allowed: keyframes in increasing step order, each step once)");
    k.position =
        parse_keyframe_point(km.require("position", detail::point_allowed() + " (distance: a number or fit)"), true);
    if (const auto p = km.get("look_at")) k.look_at = parse_keyframe_point(*p, false);
    k.fov = km.number_or("fov", k.fov, Range::open(0.0, 180.0));
    if (detail::plainly_same(k.position, k.look_at))
      km.get("position")->fail("keyframe position equals look_at (allowed: a point other than look_at)");
    c.keyframes.push_back(k);
  }
}

}  // namespace

namespace detail {

TriggerSpec parse_trigger(const Value& v) {
  // The keys, exactly one of which is given, each with what it takes: `{every: N}, {at: [steps]}
  // or {when: {above: X}}`
  const KeyShape when_keys[] = {{"above", "X"}};
  const std::string when_allowed = braced(when_keys);
  const KeyShape keys[] = {{"every", "N"}, {"at", "[steps]"}, {"when", when_allowed}};
  std::vector<std::string> names, each;
  for (const KeyShape& k : keys) {
    names.emplace_back(k.name);
    each.push_back(braced({&k, 1}));
  }
  const std::string allowed = join_words(each);
  const Map m = v.map(allowed);
  m.allow(keys);
  if (m.size() != 1) v.fail("give exactly one of " + join_words(names, ", ") + " (allowed: " + allowed + ")");
  TriggerSpec t;
  if (const auto e = m.get("every")) {
    t.kind = TriggerSpec::Kind::Every;
    t.every = e->integer(1, std::numeric_limits<std::int64_t>::max());
  } else if (const auto a = m.get("at")) {
    t.kind = TriggerSpec::Kind::At;
    const ValueList steps = a->list("a list of steps (integers >= 0)", 1);
    t.at.reserve(steps.size());
    for (const Value& s : steps) t.at.push_back(s.integer(0, std::numeric_limits<std::int64_t>::max()));
  } else {
    const Value w = *m.get("when");
    const Map wm = w.map(when_allowed);
    wm.allow(when_keys);
    t.kind = TriggerSpec::Kind::When;
    t.above = wm.require("above", "a number: the field maximum that fires the trigger").number();
  }
  return t;
}

CameraSpec parse_camera(const Value& v) {
  const Map m =
      v.map_with_keys({"position", "look_at", "up", "fov", "aperture", "focus_distance", "keyframes", "interpolation"});
  CameraSpec c;
  if (const auto k = m.get("keyframes")) {
    parse_keyframes(m, *k, c);
    return c;
  }
  if (const auto i = m.get("interpolation"))
    i->fail("interpolation is how keyframes are joined, and this camera has none (allowed: interpolation beside "
            "keyframes)");
  if (const auto p = m.get("position")) c.position = parse_point(*p, true);
  else c.position = default_camera_position();
  if (const auto p = m.get("look_at")) c.look_at = parse_point(*p);
  parse_camera_common(m, c);
  c.fov = m.number_or("fov", c.fov, Range::open(0.0, 180.0));

  // A camera that looks at its own position is caught here when it is plain to see
  if (plainly_same(c.position, c.look_at)) {
    m.get("position")->fail("camera position equals look_at (allowed: a point other than look_at)");
  }
  return c;
}

OutputSpec parse_output(const Value& v) {
  const Map m = v.map_with_keys({"file", "formats", "exposure", "tonemap", "variance", "samples", "cinema"});
  OutputSpec o;
  if (const auto f = m.get("file")) {
    o.file = f->string();
    try {
      validate_output_pattern(o.file);
    } catch (const std::invalid_argument& e) {
      f->fail(e.what());
    }
  }
  if (const auto f = m.get("formats")) {
    o.formats.clear();
    const auto formats = image_formats();
    for (const Value& e :
         f->list("a list of formats: " + detail::join_words(detail::names_of(formats), ", "), 1, formats.size())) {
      const ImageFormat fmt = e.choice(formats);
      if (o.has_format(fmt)) e.fail(std::string(image_format(fmt).name) + " given twice (allowed: each format once)");
      o.formats.push_back(fmt);
    }
  }
  o.exposure = m.number_or("exposure", o.exposure, Range::closed(-64.0, 64.0));
  o.tonemap = m.choice_or("tonemap", o.tonemap, detail::kToneMapNames);
  o.variance = m.boolean_or("variance", o.variance);
  o.samples = m.boolean_or("samples", o.samples);
  if (const auto c = m.get("cinema")) {
    const Map cm = c->map_with_keys({"azimuth", "elevation"}, " (lists of degrees)");
    CinemaSpec cs;
    if (const auto a = cm.get("azimuth"))
      for (const Value& e : a->list("a list of angles in degrees", 1)) cs.azimuths.push_back(e.number());
    if (const auto a = cm.get("elevation"))
      for (const Value& e : a->list("a list of angles in degrees", 1))
        cs.elevations.push_back(e.number(Range::closed(kMinElevation, kMaxElevation)));
    const std::size_t views =
        std::max<std::size_t>(1, cs.azimuths.size()) * std::max<std::size_t>(1, cs.elevations.size());
    if (views > CinemaSpec::kMaxViews)
      c->fail(std::to_string(cs.azimuths.size()) + " azimuths x " + std::to_string(cs.elevations.size()) +
              " elevations make " + std::to_string(views) + " views (allowed: at most " +
              std::to_string(CinemaSpec::kMaxViews) + " views per render)");
    o.cinema = cs;
  }
  return o;
}

/// A published field's name: 1 to kMaxFieldName printable characters.
std::string field_name(const Value& f) {
  std::string name = f.string();
  const bool printable =
      std::all_of(name.begin(), name.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x20 && c != 0x7f; });
  if (!printable || name.size() > kMaxFieldName)
    f.fail(f.describe() + " is not a field name (allowed: 1 to " + std::to_string(kMaxFieldName) +
           " printable characters)");
  return name;
}

/// `field: name` or `field: {magnitude: [a, b, c]}` (RenderSpec::magnitude).
void parse_field(const Value& f, RenderSpec& r) {
  if (!f.is_map()) {
    r.field = field_name(f);
    return;
  }
  const Map m = f.map_with_keys({"magnitude"}, "(or a field name)");
  const auto names = m.get("magnitude");
  if (!names) f.fail(f.path() + " is a mapping without `magnitude` (allowed: a field name, or {magnitude: [a, b, c]})");
  for (const Value& n : names->list("a list of three field names", 3, 3)) r.magnitude.push_back(field_name(n));
  r.field = "|" + r.magnitude[0] + ", " + r.magnitude[1] + ", " + r.magnitude[2] + "|";
}

}  // namespace detail

bool RenderSpec::uses(const std::string& published) const {
  if (field.empty()) return true;
  if (magnitude.empty()) return field == published;
  return std::find(magnitude.begin(), magnitude.end(), published) != magnitude.end();
}

std::string RenderSpec::field_key() const {
  // A render's field name never holds a control character (the parser refuses them), so no
  // scalar render's key equals a magnitude's
  return magnitude.empty() ? field : "\x01magnitude\x01" + magnitude[0] + "\x01" + magnitude[1] + "\x01" + magnitude[2];
}

namespace detail {

RenderSpec parse_render(const Value& v, const std::function<std::string(const std::string&)>& unique_name) {
  const Map m = v.map_with_keys({"name", "field", "trigger", "image", "camera", "transfer_function", "lights",
                                 "background", "integrator", "output", "annotations"});
  RenderSpec r;
  if (const auto name = m.get("name")) {
    r.name = name->string();
    if (!valid_name(r.name)) {
      name->fail(name->describe() + " is not a valid name (allowed: 1 to " + std::to_string(kMaxRenderName) +
                 " letters, digits, _ and -)");
    }
  }
  if (const auto f = m.get("field")) parse_field(*f, r);
  if (r.name.empty())
    r.name = unique_name(
        r.magnitude.empty() ? r.field : r.magnitude[0] + "_" + r.magnitude[1] + "_" + r.magnitude[2] + "_magnitude");
  if (const auto t = m.get("trigger")) r.trigger = parse_trigger(*t);
  if (const auto i = m.get("image")) parse_image(*i, r);
  if (const auto c = m.get("camera")) r.camera = parse_camera(*c);
  else r.camera.position = default_camera_position();

  // No transfer function: the default look, its light and background too where not given
  if (const auto tf = m.get("transfer_function")) {
    r.transfer_function = parse_transfer_function(*tf);
  } else {
    r.transfer_function = default_transfer_function();
    if (!m.has("lights")) r.lights = default_lights();
    if (!m.has("background")) r.background = default_background();
  }
  if (const auto l = m.get("lights")) {
    std::vector<std::string> shapes;
    for (const std::string& type : detail::names_of(detail::kLightTypeNames))
      shapes.push_back("{type: " + type + ", ...}");
    for (const Value& e : l->list("a list of lights, each " + detail::join_words(shapes)))
      r.lights.push_back(parse_light(e));
  }
  if (const auto b = m.get("background")) r.background = parse_background(*b);
  if (const auto i = m.get("integrator")) r.integrator = parse_integrator(*i);
  if (const auto o = m.get("output")) r.output = parse_output(*o);
  if (const auto a = m.get("annotations")) r.annotations = parse_annotations(*a, r);
  return r;
}

}  // namespace detail

bool OutputSpec::has_format(ImageFormat f) const {
  return std::find(formats.begin(), formats.end(), f) != formats.end();
}

}  // namespace tessera::config
