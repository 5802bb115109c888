// The effective config as YAML: every default written out, accepted again by parse_config.
#include <tessera/config/config.h>
#include <tessera/image_format.h>

#include "enum_names.h"
#include "yaml_reader.h"

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace tessera::config {
namespace {

using tessera::format_number;
using detail::name_of;

// `write(out, x)` writes x as one YAML node, chosen by the type of x; `field(out, key, x)` writes
// a map entry. Every overload is declared here, before the templates that call them.

/// Strings are always double-quoted so that names like `null` or `123` stay strings.
void write(YAML::Emitter& out, const std::string& s) { out << YAML::DoubleQuoted << s; }
/// Keywords and enum names: plain scalars.
void write(YAML::Emitter& out, const char* word) { out << word; }
void write(YAML::Emitter& out, double v) { out << format_number(v); }
void write(YAML::Emitter& out, bool b) { out << b; }
void write(YAML::Emitter& out, int v) { out << v; }
void write(YAML::Emitter& out, std::int64_t v) { out << v; }
/// Seeds: all 64 bits, as digits.
void write(YAML::Emitter& out, std::uint64_t v) { out << std::to_string(v); }
void write(YAML::Emitter& out, const Vec3& v);
void write(YAML::Emitter& out, const OrbitValue& v);
void write(YAML::Emitter& out, const PointSpec& p);
void write(YAML::Emitter& out, const LengthSpec& l);
void write(YAML::Emitter& out, const ScalarPoint& p);
void write(YAML::Emitter& out, const ColorPoint& p);
void write(YAML::Emitter& out, const ColorTFSpec& tf);
void write(YAML::Emitter& out, ImageFormat f);
void write(YAML::Emitter& out, const GlobalOptions& g);
void write(YAML::Emitter& out, const VolumeSpec& v);
void write(YAML::Emitter& out, const TriggerSpec& t);
void write_image(YAML::Emitter& out, const RenderSpec& r);
void write(YAML::Emitter& out, const CameraSpec& c);
void write(YAML::Emitter& out, const TransferFunctionSpec& tf);
void write(YAML::Emitter& out, const LightSpec& l);
void write(YAML::Emitter& out, const BackgroundSpec& b);
void write(YAML::Emitter& out, const IntegratorSpec& s);
void write(YAML::Emitter& out, const OutputSpec& o);
void write(YAML::Emitter& out, const RenderSpec& r);
template <class T>
void write(YAML::Emitter& out, const std::vector<T>& xs);

void key(YAML::Emitter& out, const char* k) { out << YAML::Key << k << YAML::Value; }

template <class T>
void field(YAML::Emitter& out, const char* k, const T& v) {
  key(out, k);
  write(out, v);
}

/// `[a, b, ...]` on one line. Inside a flow node yaml-cpp writes every child in flow style
/// anyway, so this and the list overload below serve at any depth.
template <class... Ts>
void flow_seq(YAML::Emitter& out, const Ts&... xs) {
  out << YAML::Flow << YAML::BeginSeq;
  (write(out, xs), ...);
  out << YAML::EndSeq;
}

/// A list on one line, `[x0, x1, ...]`.
template <class T>
void write(YAML::Emitter& out, const std::vector<T>& xs) {
  out << YAML::Flow << YAML::BeginSeq;
  for (const T& x : xs) write(out, x);
  out << YAML::EndSeq;
}

void write(YAML::Emitter& out, const Vec3& v) { flow_seq(out, v.x, v.y, v.z); }

/// An orbit value: the plain number, or `{start: S, per_step: D}` when it moves.
void write(YAML::Emitter& out, const OrbitValue& v) {
  if (!v.moves()) return write(out, v.start);
  out << YAML::Flow << YAML::BeginMap;
  field(out, "start", v.start);
  field(out, "per_step", v.per_step);
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const PointSpec& p) {
  switch (p.kind) {
    case PointSpec::Kind::Center: out << "center"; return;
    case PointSpec::Kind::Absolute: write(out, p.xyz); return;
    case PointSpec::Kind::Orbit:
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "orbit" << YAML::Value << YAML::BeginMap;
      field(out, "azimuth", p.orbit.azimuth);
      field(out, "elevation", p.orbit.elevation);
      // `fit` stays a word so the written config re-frames when the data or image changes
      if (p.orbit.fit) out << YAML::Key << "distance" << YAML::Value << "fit";
      else field(out, "distance", p.orbit.distance);
      out << YAML::EndMap << YAML::EndMap;
      return;
  }
}

void write(YAML::Emitter& out, const LengthSpec& l) {
  if (!l.relative) return write(out, l.value);
  out << YAML::Flow << YAML::BeginMap;
  field(out, "relative", l.value);
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const ScalarPoint& p) { flow_seq(out, p.u, p.v); }
void write(YAML::Emitter& out, const ColorPoint& p) { flow_seq(out, p.u, p.c); }

void write(YAML::Emitter& out, const ColorTFSpec& tf) {
  if (!tf.colormap.empty()) return write(out, tf.colormap);
  write(out, tf.points);
}

void write(YAML::Emitter& out, ImageFormat f) { write(out, image_format(f).name); }

void write(YAML::Emitter& out, const GlobalOptions& g) {
  out << YAML::BeginMap;
  field(out, "output_dir", g.output_dir);
  field(out, "on_error", name_of(detail::kOnErrorNames, g.on_error));
  field(out, "threads", g.threads);
  field(out, "render_final_step", g.render_final_step);
  field(out, "max_failures", g.max_failures);
  field(out, "time_limit", g.time_limit);
  field(out, "memory_limit_mb", g.memory_limit_mb);
  field(out, "distribution", name_of(detail::kDistributionNames, g.distribution));
  field(out, "brick_cache", g.brick_cache);
  if (g.budget > 0.0) field(out, "budget", g.budget);  // no budget: the key left out
  field(out, "device", name_of(detail::kDeviceNames, g.device));
  field(out, "cuda_device", g.cuda_device);
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const VolumeSpec& v) {
  out << YAML::BeginMap;
  field(out, "file", v.file);
  key(out, "dims");
  flow_seq(out, v.dims[0], v.dims[1], v.dims[2]);
  field(out, "dtype", name_of(detail::kDTypeNames, v.dtype));
  field(out, "spacing", v.spacing);
  field(out, "origin", v.origin);
  field(out, "byte_order", name_of(detail::kByteOrderNames, v.byte_order));
  field(out, "header_bytes", v.header_bytes);
  field(out, "association", name_of(detail::kAssociationNames, v.association));
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const TriggerSpec& t) {
  out << YAML::Flow << YAML::BeginMap;
  switch (t.kind) {
    case TriggerSpec::Kind::Every: field(out, "every", t.every); break;
    case TriggerSpec::Kind::At: field(out, "at", t.at); break;
    case TriggerSpec::Kind::When:
      key(out, "when");
      out << YAML::BeginMap;
      field(out, "above", t.above);
      out << YAML::EndMap;
      break;
  }
  out << YAML::EndMap;
}

/// `image:`: the core ImageDesc and the render's min_spp.
void write_image(YAML::Emitter& out, const RenderSpec& r) {
  const ImageDesc& image = r.image;
  out << YAML::Flow << YAML::BeginMap;
  field(out, "width", image.width);
  field(out, "height", image.height);
  field(out, "spp", image.spp);
  field(out, "min_spp", r.min_spp);
  field(out, "target_error", image.target_error);
  field(out, "denoise", image.denoise);
  out << YAML::EndMap;
}

/// A keyframed camera: its keyframes as a block list of one-line maps, then how they are joined.
void write_keyframes(YAML::Emitter& out, const CameraSpec& c) {
  key(out, "keyframes");
  out << YAML::BeginSeq;
  for (const CameraKeyframe& k : c.keyframes) {
    out << YAML::Flow << YAML::BeginMap;
    field(out, "step", k.step);
    field(out, "position", k.position);
    field(out, "look_at", k.look_at);
    field(out, "fov", k.fov);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  field(out, "interpolation", name_of(detail::kCameraInterpolationNames, c.interpolation));
}

void write(YAML::Emitter& out, const CameraSpec& c) {
  out << YAML::BeginMap;
  if (c.keyframes.empty()) {
    field(out, "position", c.position);
    field(out, "look_at", c.look_at);
  } else {
    write_keyframes(out, c);
  }
  field(out, "up", c.up);
  if (c.keyframes.empty()) field(out, "fov", c.fov);
  field(out, "aperture", c.aperture);
  field(out, "focus_distance", c.focus_distance);
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const TransferFunctionSpec& tf) {
  out << YAML::BeginMap;
  key(out, "range");
  if (tf.range.automatic) out << "auto";
  else flow_seq(out, tf.range.lo, tf.range.hi);
  // Relative to the data's diagonal: the optical depth, resolved per render by build_scene
  if (tf.density_relative) {
    key(out, "density_scale");
    out << YAML::Flow << YAML::BeginMap;
    field(out, "optical_depth", tf.density_scale);
    out << YAML::EndMap;
  } else {
    field(out, "density_scale", tf.density_scale);
  }
  field(out, "opacity", tf.opacity);
  if (tf.diffuse.present()) field(out, "diffuse", tf.diffuse);
  if (tf.specular.present()) field(out, "specular", tf.specular);
  if (tf.emission.present()) field(out, "emission", tf.emission);
  if (!tf.roughness.empty()) field(out, "roughness", tf.roughness);
  out << YAML::EndMap;
}

// Each kind's own keys, one overload per alternative of LightSpec (written between
// `position` and `color`)

void write_kind_keys(YAML::Emitter& out, const RectLightSpec& l) {
  field(out, "target", l.target);
  key(out, "size");
  flow_seq(out, l.width, l.height);
}

void write_kind_keys(YAML::Emitter& out, const SphereLightSpec& l) { field(out, "radius", l.radius); }

void write(YAML::Emitter& out, const LightSpec& light) {
  out << YAML::Flow << YAML::BeginMap;
  field(out, "type", detail::light_type_name(light));
  std::visit(
      [&out](const auto& l) {
        field(out, "position", l.position);
        write_kind_keys(out, l);
        field(out, "color", l.color);
        field(out, "intensity", l.intensity);
      },
      light);
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const BackgroundSpec& b) {
  out << YAML::BeginMap;
  field(out, "type", name_of(detail::kBackgroundTypeNames, b.type));
  switch (b.type) {
    case BackgroundType::Constant: field(out, "color", b.color); break;
    case BackgroundType::Gradient:
      field(out, "top", b.top);
      field(out, "middle", b.middle);
      field(out, "bottom", b.bottom);
      field(out, "up", b.up);
      break;
    case BackgroundType::EnvMap:
      field(out, "file", b.file);
      field(out, "up", b.up);
      break;
  }
  field(out, "intensity", b.intensity);
  field(out, "visible", b.visible);
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const IntegratorSpec& s) {
  const IntegratorDesc& d = s.desc;
  out << YAML::BeginMap;
  field(out, "scattering", name_of(detail::kScatteringNames, d.scattering));
  field(out, "max_bounces", d.max_bounces);
  field(out, "rr_depth", d.rr_depth);
  field(out, "shading", name_of(detail::kShadingNames, d.shading));
  field(out, "gradient_factor", d.gradient_factor);
  field(out, "phase_g", d.phase_g);
  field(out, "free_path", name_of(detail::kFreePathNames, d.free_path));
  field(out, "majorant", name_of(detail::kMajorantNames, d.majorant));
  field(out, "macrocell", d.macrocell);
  field(out, "step", d.step);
  field(out, "shadow", name_of(detail::kShadowNames, d.shadow));
  field(out, "shadow_roulette", d.shadow_roulette);
  field(out, "culling", d.culling);
  field(out, "sampler", name_of(detail::kSamplerNames, d.sampler));
  field(out, "seed", s.seed);
  field(out, "tile", s.tile);
  field(out, "tile_order", name_of(detail::kTileOrderNames, s.tile_order));
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const OutputSpec& o) {
  out << YAML::BeginMap;
  field(out, "file", o.file);
  field(out, "formats", o.formats);
  field(out, "exposure", o.exposure);
  field(out, "tonemap", name_of(detail::kToneMapNames, o.tonemap));
  field(out, "variance", o.variance);
  field(out, "samples", o.samples);
  if (o.cinema) {
    key(out, "cinema");
    out << YAML::BeginMap;
    if (!o.cinema->azimuths.empty()) field(out, "azimuth", o.cinema->azimuths);
    if (!o.cinema->elevations.empty()) field(out, "elevation", o.cinema->elevations);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const AnnotationsSpec& a) {
  out << YAML::BeginMap;
  key(out, "colorbar");
  if (!a.colorbar) {
    out << false;
  } else {
    const ColorBarSpec& b = a.bar;
    out << YAML::BeginMap;
    field(out, "corner", name_of(detail::kCornerNames, b.corner));
    field(out, "orientation", name_of(detail::kOrientationNames, b.orientation));
    field(out, "length", b.length);
    field(out, "thickness", b.thickness);
    field(out, "ticks", b.ticks);
    if (b.label) field(out, "label", *b.label);
    out << YAML::EndMap;
  }
  if (!a.text.empty()) field(out, "text", a.text);
  field(out, "text_corner", name_of(detail::kCornerNames, a.text_corner));
  if (!a.title.empty()) field(out, "title", a.title);
  field(out, "title_corner", name_of(detail::kCornerNames, a.title_corner));
  field(out, "font", a.font);
  field(out, "font_size", a.font_size);
  out << YAML::EndMap;
}

void write(YAML::Emitter& out, const RenderSpec& r) {
  out << YAML::BeginMap;
  field(out, "name", r.name);
  if (!r.magnitude.empty()) {
    key(out, "field");
    out << YAML::BeginMap << YAML::Key << "magnitude" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const std::string& name : r.magnitude) out << name;
    out << YAML::EndSeq << YAML::EndMap;
  } else if (!r.field.empty()) {
    field(out, "field", r.field);
  }
  if (r.trigger) field(out, "trigger", *r.trigger);
  key(out, "image");
  write_image(out, r);
  field(out, "camera", r.camera);
  field(out, "transfer_function", r.transfer_function);
  // Lights: a block list of one-line maps, `[]` when there are none
  key(out, "lights");
  if (r.lights.empty()) out << YAML::Flow;
  out << YAML::BeginSeq;
  for (const auto& l : r.lights) write(out, l);
  out << YAML::EndSeq;
  field(out, "background", r.background);
  field(out, "integrator", r.integrator);
  field(out, "output", r.output);
  if (r.annotations) {
    key(out, "annotations");
    write(out, *r.annotations);
  }
  out << YAML::EndMap;
}

}  // namespace

std::string to_yaml(const Config& c) {
  YAML::Emitter out;
  out.SetBoolFormat(YAML::TrueFalseBool);
  out << YAML::BeginMap;
  field(out, "tessera", c.global);
  if (c.volume) field(out, "volume", *c.volume);
  key(out, "renders");
  out << YAML::BeginSeq;
  for (const auto& r : c.renders) write(out, r);
  out << YAML::EndSeq;
  out << YAML::EndMap;
  if (!out.good()) throw std::logic_error("to_yaml: " + out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

}  // namespace tessera::config
