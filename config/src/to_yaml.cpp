// The effective config as YAML: every default written out, accepted again by parse_config.
#include <tessera/config/config.h>

#include "yaml_reader.h"

#include <yaml-cpp/yaml.h>

#include <string>

namespace tessera::config {
namespace {

using detail::format_number;

/// Strings are always double-quoted so that names like `null` or `123` stay strings.
void str(YAML::Emitter& out, const std::string& s) { out << YAML::DoubleQuoted << s; }
void num(YAML::Emitter& out, double v) { out << format_number(v); }

void vec3(YAML::Emitter& out, const Vec3& v) {
  out << YAML::Flow << YAML::BeginSeq;
  num(out, v.x);
  num(out, v.y);
  num(out, v.z);
  out << YAML::EndSeq;
}

void point(YAML::Emitter& out, const PointSpec& p) {
  switch (p.kind) {
    case PointSpec::Kind::Center: out << "center"; return;
    case PointSpec::Kind::Absolute: vec3(out, p.xyz); return;
    case PointSpec::Kind::Orbit:
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "orbit" << YAML::Value << YAML::BeginMap;
      out << YAML::Key << "azimuth" << YAML::Value;
      num(out, p.orbit.azimuth);
      out << YAML::Key << "elevation" << YAML::Value;
      num(out, p.orbit.elevation);
      out << YAML::Key << "distance" << YAML::Value;
      num(out, p.orbit.distance);
      out << YAML::EndMap << YAML::EndMap;
      return;
  }
}

void length(YAML::Emitter& out, const LengthSpec& l) {
  if (!l.relative) return num(out, l.value);
  out << YAML::Flow << YAML::BeginMap << YAML::Key << "relative" << YAML::Value;
  num(out, l.value);
  out << YAML::EndMap;
}

void scalar_points(YAML::Emitter& out, const std::vector<ScalarPoint>& pts) {
  out << YAML::Flow << YAML::BeginSeq;
  for (const auto& p : pts) {
    out << YAML::BeginSeq;
    num(out, p.u);
    num(out, p.v);
    out << YAML::EndSeq;
  }
  out << YAML::EndSeq;
}

void color_tf(YAML::Emitter& out, const ColorTFSpec& tf) {
  if (!tf.colormap.empty()) return str(out, tf.colormap);
  out << YAML::Flow << YAML::BeginSeq;
  for (const auto& p : tf.points) {
    out << YAML::BeginSeq;
    num(out, p.u);
    vec3(out, p.c);
    out << YAML::EndSeq;
  }
  out << YAML::EndSeq;
}

void key(YAML::Emitter& out, const char* k) { out << YAML::Key << k << YAML::Value; }

void emit_global(YAML::Emitter& out, const GlobalOptions& g) {
  out << YAML::BeginMap;
  key(out, "output_dir");
  str(out, g.output_dir);
  key(out, "on_error");
  out << on_error_name(g.on_error);
  key(out, "threads");
  out << g.threads;
  key(out, "render_final_step");
  out << g.render_final_step;
  key(out, "max_failures");
  out << g.max_failures;
  out << YAML::EndMap;
}

void emit_volume(YAML::Emitter& out, const VolumeSpec& v) {
  out << YAML::BeginMap;
  key(out, "file");
  str(out, v.file);
  key(out, "dims");
  out << YAML::Flow << YAML::BeginSeq << v.dims[0] << v.dims[1] << v.dims[2] << YAML::EndSeq;
  key(out, "dtype");
  out << dtype_name(v.dtype);
  key(out, "spacing");
  vec3(out, v.spacing);
  key(out, "origin");
  vec3(out, v.origin);
  key(out, "byte_order");
  out << (v.byte_order == ByteOrder::Big ? "big" : "little");
  key(out, "header_bytes");
  out << v.header_bytes;
  out << YAML::EndMap;
}

void emit_trigger(YAML::Emitter& out, const TriggerSpec& t) {
  out << YAML::Flow << YAML::BeginMap;
  switch (t.kind) {
    case TriggerSpec::Kind::Every: key(out, "every"); out << t.every; break;
    case TriggerSpec::Kind::At:
      key(out, "at");
      out << YAML::BeginSeq;
      for (auto s : t.at) out << s;
      out << YAML::EndSeq;
      break;
    case TriggerSpec::Kind::When:
      key(out, "when");
      out << YAML::BeginMap;
      key(out, "above");
      num(out, t.above);
      out << YAML::EndMap;
      break;
  }
  out << YAML::EndMap;
}

void emit_camera(YAML::Emitter& out, const CameraSpec& c) {
  out << YAML::BeginMap;
  key(out, "position");
  point(out, c.position);
  key(out, "look_at");
  point(out, c.look_at);
  key(out, "up");
  vec3(out, c.up);
  key(out, "fov");
  num(out, c.fov);
  key(out, "aperture");
  num(out, c.aperture);
  key(out, "focus_distance");
  num(out, c.focus_distance);
  out << YAML::EndMap;
}

void emit_tf(YAML::Emitter& out, const TransferFunctionSpec& tf) {
  out << YAML::BeginMap;
  key(out, "range");
  if (tf.range.automatic) {
    out << "auto";
  } else {
    out << YAML::Flow << YAML::BeginSeq;
    num(out, tf.range.lo);
    num(out, tf.range.hi);
    out << YAML::EndSeq;
  }
  key(out, "density_scale");
  num(out, tf.density_scale);
  key(out, "opacity");
  scalar_points(out, tf.opacity);
  const std::pair<const char*, const ColorTFSpec*> colors[] = {
      {"diffuse", &tf.diffuse}, {"specular", &tf.specular}, {"emission", &tf.emission}};
  for (const auto& [name, c] : colors) {
    if (!c->present()) continue;
    key(out, name);
    color_tf(out, *c);
  }
  if (!tf.roughness.empty()) {
    key(out, "roughness");
    scalar_points(out, tf.roughness);
  }
  out << YAML::EndMap;
}

void emit_light(YAML::Emitter& out, const LightSpec& l) {
  out << YAML::Flow << YAML::BeginMap;
  const bool rect = l.type == LightSpec::Type::Rect;
  key(out, "type");
  out << (rect ? "rect" : "sphere");
  key(out, "position");
  point(out, l.position);
  if (rect) {
    key(out, "target");
    point(out, l.target);
    key(out, "size");
    out << YAML::BeginSeq;
    length(out, l.width);
    length(out, l.height);
    out << YAML::EndSeq;
  } else {
    key(out, "radius");
    length(out, l.radius);
  }
  key(out, "color");
  vec3(out, l.color);
  key(out, "intensity");
  num(out, l.intensity);
  out << YAML::EndMap;
}

void emit_background(YAML::Emitter& out, const BackgroundSpec& b) {
  out << YAML::BeginMap;
  key(out, "type");
  switch (b.type) {
    case BackgroundType::Constant:
      out << "constant";
      key(out, "color");
      vec3(out, b.color);
      break;
    case BackgroundType::Gradient:
      out << "gradient";
      key(out, "top");
      vec3(out, b.top);
      key(out, "middle");
      vec3(out, b.middle);
      key(out, "bottom");
      vec3(out, b.bottom);
      key(out, "up");
      vec3(out, b.up);
      break;
    case BackgroundType::EnvMap:
      out << "envmap";
      key(out, "file");
      str(out, b.file);
      key(out, "up");
      vec3(out, b.up);
      break;
  }
  key(out, "intensity");
  num(out, b.intensity);
  key(out, "visible");
  out << b.visible;
  out << YAML::EndMap;
}

void emit_integrator(YAML::Emitter& out, const IntegratorSpec& s) {
  const IntegratorDesc& d = s.desc;
  out << YAML::BeginMap;
  key(out, "scattering");
  out << (d.scattering == Scattering::Single ? "single" : "multiple");
  key(out, "max_bounces");
  out << d.max_bounces;
  key(out, "rr_depth");
  out << d.rr_depth;
  key(out, "shading");
  out << (d.shading == Shading::Phase ? "phase" : d.shading == Shading::Brdf ? "brdf" : "hybrid");
  key(out, "gradient_factor");
  num(out, d.gradient_factor);
  key(out, "phase_g");
  num(out, d.phase_g);
  key(out, "free_path");
  out << (d.free_path == FreePath::Delta ? "delta" : "raymarch");
  key(out, "majorant");
  out << (d.majorant == MajorantMode::Grid ? "grid" : "global");
  key(out, "macrocell");
  out << d.macrocell;
  key(out, "step");
  num(out, d.step);
  key(out, "shadow");
  out << (d.shadow == ShadowMode::Ratio ? "ratio" : "delta");
  key(out, "shadow_roulette");
  out << d.shadow_roulette;
  key(out, "culling");
  out << d.culling;
  key(out, "seed");
  out << std::to_string(s.seed);
  key(out, "tile");
  out << s.tile;
  key(out, "tile_order");
  out << (s.tile_order == TileOrder::RowMajor ? "row" : "morton");
  out << YAML::EndMap;
}

void emit_output(YAML::Emitter& out, const OutputSpec& o) {
  out << YAML::BeginMap;
  key(out, "file");
  str(out, o.file);
  key(out, "formats");
  out << YAML::Flow << YAML::BeginSeq;
  for (auto f : o.formats) out << format_name(f);
  out << YAML::EndSeq;
  key(out, "exposure");
  num(out, o.exposure);
  key(out, "tonemap");
  out << (o.tonemap == ToneMap::Curve::Aces       ? "aces"
          : o.tonemap == ToneMap::Curve::Reinhard ? "reinhard"
                                                  : "clamp");
  key(out, "variance");
  out << o.variance;
  key(out, "samples");
  out << o.samples;
  if (o.cinema) {
    key(out, "cinema");
    out << YAML::BeginMap;
    const std::pair<const char*, const std::vector<double>*> lists[] = {
        {"azimuth", &o.cinema->azimuths}, {"elevation", &o.cinema->elevations}};
    for (const auto& [name, xs] : lists) {
      if (xs->empty()) continue;
      key(out, name);
      out << YAML::Flow << YAML::BeginSeq;
      for (double x : *xs) num(out, x);
      out << YAML::EndSeq;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

void emit_render(YAML::Emitter& out, const RenderSpec& r) {
  out << YAML::BeginMap;
  key(out, "name");
  str(out, r.name);
  if (!r.field.empty()) {
    key(out, "field");
    str(out, r.field);
  }
  if (r.trigger) {
    key(out, "trigger");
    emit_trigger(out, *r.trigger);
  }
  key(out, "image");
  out << YAML::Flow << YAML::BeginMap;
  key(out, "width");
  out << r.image.width;
  key(out, "height");
  out << r.image.height;
  key(out, "spp");
  out << r.image.spp;
  key(out, "target_error");
  num(out, r.image.target_error);
  out << YAML::EndMap;
  key(out, "camera");
  emit_camera(out, r.camera);
  key(out, "transfer_function");
  emit_tf(out, r.transfer_function);
  key(out, "lights");
  if (r.lights.empty()) out << YAML::Flow;
  out << YAML::BeginSeq;
  for (const auto& l : r.lights) emit_light(out, l);
  out << YAML::EndSeq;
  key(out, "background");
  emit_background(out, r.background);
  key(out, "integrator");
  emit_integrator(out, r.integrator);
  key(out, "output");
  emit_output(out, r.output);
  out << YAML::EndMap;
}

}  // namespace

std::string to_yaml(const Config& c) {
  YAML::Emitter out;
  out.SetBoolFormat(YAML::TrueFalseBool);
  out << YAML::BeginMap;
  key(out, "tessera");
  emit_global(out, c.global);
  if (c.volume) {
    key(out, "volume");
    emit_volume(out, *c.volume);
  }
  key(out, "renders");
  out << YAML::BeginSeq;
  for (const auto& r : c.renders) emit_render(out, r);
  out << YAML::EndSeq;
  out << YAML::EndMap;
  if (!out.good()) throw std::logic_error("to_yaml: " + out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

}  // namespace tessera::config
