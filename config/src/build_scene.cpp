// RenderSpec -> tessera::SceneDesc, once the data bounds and value range are known.
#include <tessera/config/build_scene.h>
#include <tessera/config/camera_keyframes.h>
#include <tessera/config/colormaps.h>
#include <tessera/image_io.h>
#include <tessera/loop_bounds.h>

#include "yaml_reader.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <variant>

namespace tessera::config {
namespace {

ScalarTF to_scalar_tf(const std::vector<ScalarPoint>& pts) {
  std::vector<double> xs, vs;
  for (const auto& p : pts) {
    xs.push_back(p.u);
    vs.push_back(p.v);
  }
  return ScalarTF(xs, vs);
}

ColorTF to_color_tf(const ColorTFSpec& spec) {
  const std::vector<ColorPoint> pts = spec.colormap.empty() ? spec.points : colormap(spec.colormap);
  std::vector<double> xs;
  std::vector<Color> vs;
  for (const auto& p : pts) {
    xs.push_back(p.u);
    vs.push_back(p.c);
  }
  return ColorTF(xs, vs);
}

using tessera::format_number;

std::string vec_text(const Vec3& v) {
  std::string out = "[";
  out += format_number(v.x);
  out += ", ";
  out += format_number(v.y);
  out += ", ";
  out += format_number(v.z);
  out += "]";
  return out;
}

/// Resolved points and lengths: finite (an orbit distance times a huge data radius
/// overflows) and within kMaxCoordinateVoxels smallest spacings of 0, as prepare() requires,
/// here with the config's key (lights[i], not prepare's per-type index).
struct Resolver {
  const std::string& render;
  double lim;  ///< kMaxCoordinateVoxels * smallest spacing

  Vec3 point(const std::string& key, const Vec3& p) const {
    if (!is_finite(p))
      fail(key + " is not finite after resolving (" + vec_text(p) +
           "; an orbit distance times the data radius overflows)");
    if (std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) > lim)
      fail(key + " " + vec_text(p) + " lies beyond 2^40 smallest spacings (" + format_number(lim) +
           ") from 0, where a double no longer resolves a voxel");
    return p;
  }
  double length(const std::string& key, double v) const {
    if (!std::isfinite(v))
      fail(key + " is not finite after resolving (" + format_number(v) +
           "; relative size times the data radius overflows)");
    if (v > lim)
      fail(key + " " + format_number(v) + " is larger than 2^40 smallest spacings (" + format_number(lim) + ")");
    return v;
  }
  /// The point at simulation step `step`: each moving orbit value S + D * n, checked against
  /// its key's range as a plain number is when the config is loaded.
  PointSpec at_step(const std::string& key, const PointSpec& p, std::int64_t step) const {
    if (!p.moves()) return p;
    PointSpec q = p;
    q.orbit = p.orbit.at(step);
    const auto check = [&](const char* name, const OrbitValue& v, double at, double lo, double hi,
                           const std::string& allowed) {
      if (std::isfinite(at) && at >= lo && at <= hi) return;
      fail(key + ": orbit " + name + " {start: " + format_number(v.start) + ", per_step: " + format_number(v.per_step) +
           "} is " + format_number(at) + " at step " + std::to_string(step) + " (allowed: " + allowed + ")");
    };
    check("azimuth", p.orbit.azimuth, q.orbit.azimuth.start, -INFINITY, INFINITY, "a finite number");
    check("elevation", p.orbit.elevation, q.orbit.elevation.start, kMinElevation, kMaxElevation,
          "a number in [" + format_number(kMinElevation) + ", " + format_number(kMaxElevation) + "]");
    if (!p.orbit.fit)
      check("distance", p.orbit.distance, q.orbit.distance.start, kMinDistance, INFINITY,
            "a number >= " + format_number(kMinDistance));
    return q;
  }
  /// An orbit is placed in multiples of the data's bounding-sphere radius: data of one vertex
  /// (radius 0) puts it on the data itself, a fault of the data's extent, not of the camera.
  void orbit_extent(const std::string& key, const PointSpec& p, const Bounds& b) const {
    if (p.kind != PointSpec::Kind::Orbit || b.radius() > 0.0) return;
    fail(key + ": an orbit" + (p.orbit.fit ? std::string(" with distance: fit") : std::string()) +
         " is measured in the data's bounding-sphere radius, but the data's bounds are the single point " +
         vec_text(b.lo) +
         " (a volume of one vertex, dims 1x1x1), so there is nothing to frame (allowed: "
         "data with 2 or more vertices along some axis, or an absolute position [x, y, z])");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("render \"" + render + "\": " + what);
  }
};

/// Where one light's points and lengths resolve: against the data bounds, orbits about the
/// camera's up, checked by the Resolver under the light's key (`lights[i].`).
struct LightFrame {
  const Resolver& res;
  const Bounds& bounds;
  const Vec3& up;
  std::int64_t step;
  std::string key;

  Vec3 point(const char* name, const PointSpec& p) const {
    return res.point(key + name, resolve_point(res.at_step(key + name, p, step), bounds, up));
  }
  double length(const char* name, const LengthSpec& l) const {
    return res.length(key + name, l.resolve(bounds.radius()));
  }
};

// Each kind's spec as its core description, one overload per alternative of LightSpec
// (build_scene visits them); `radiance` is color * intensity, already checked

RectLightDesc resolve_light(const RectLightSpec& l, const LightFrame& f, const Color& radiance) {
  RectLightDesc r;
  r.position = f.point("position", l.position);
  r.target = f.point("target", l.target);
  r.width = f.length("size", l.width);
  r.height = f.length("size", l.height);
  r.radiance = radiance;
  return r;
}

SphereLightDesc resolve_light(const SphereLightSpec& l, const LightFrame& f, const Color& radiance) {
  SphereLightDesc sp;
  sp.center = f.point("position", l.position);
  sp.radius = f.length("radius", l.radius);
  sp.radiance = radiance;
  return sp;
}

/// Keyframe k of the render's camera, resolved against the data bounds under its key; an orbit
/// with `distance: fit` is framed with the keyframe's fov.
CameraPose resolve_keyframe(const Resolver& res, const RenderSpec& spec, std::size_t k, const Bounds& b) {
  const CameraKeyframe& f = spec.camera.keyframes[k];
  const std::string key = "camera.keyframes[" + std::to_string(k) + "].";
  res.orbit_extent(key + "position", f.position, b);
  CameraPose p;
  const double fit_radii = fit_distance(f.fov, spec.image.width, spec.image.height);
  p.position = res.point(key + "position", resolve_point(f.position, b, spec.camera.up, fit_radii));
  p.look_at = res.point(key + "look_at", resolve_point(f.look_at, b, spec.camera.up));
  p.fov = f.fov;
  if (f.position.kind == PointSpec::Kind::Orbit) {
    const OrbitSpec& o = f.position.orbit;
    p.on_orbit = true;
    p.orbit = Vec3(o.azimuth.start, o.elevation.start, o.fit ? fit_radii : o.distance.start);
  }
  return p;
}

/// A keyframed camera at simulation step n (camera_keyframes.h): only the keyframes around n are
/// resolved (2 to 4 of them, found by binary search). A pose that cannot make a camera (position on look_at,
/// view along up) fails here with the step and its keyframes, as a moving orbit does.
CameraPose keyframed_pose(const Resolver& res, const RenderSpec& spec, const Bounds& b, std::int64_t step) {
  const std::vector<CameraKeyframe>& keys = spec.camera.keyframes;
  std::vector<std::int64_t> steps;
  steps.reserve(keys.size());
  for (const CameraKeyframe& k : keys) steps.push_back(k.step);
  const KeyframeSpan span = keyframe_span(steps, step);
  const std::size_t i = span.i;
  PoseWindow w;
  w.pose[1] = resolve_keyframe(res, spec, i, b);
  w.step[1] = keys[i].step;
  std::string where = "at step " + std::to_string(step) + " (keyframe " + std::to_string(i) + ", step " +
                      std::to_string(keys[i].step) + ")";
  CameraPose p = w.pose[1];
  if (span.t > 0.0) {
    w.pose[2] = resolve_keyframe(res, spec, i + 1, b);
    w.step[2] = keys[i + 1].step;
    if (spec.camera.interpolation == CameraInterpolation::Smooth) {
      if ((w.has_before = i > 0)) {
        w.pose[0] = resolve_keyframe(res, spec, i - 1, b);
        w.step[0] = keys[i - 1].step;
      }
      if ((w.has_after = i + 2 < keys.size())) {
        w.pose[3] = resolve_keyframe(res, spec, i + 2, b);
        w.step[3] = keys[i + 2].step;
      }
    }
    p = interpolate_pose(spec.camera.interpolation, w, span.t);
    where = "at step " + std::to_string(step) + " (between keyframes " + std::to_string(i) + " and " +
            std::to_string(i + 1) + ", steps " + std::to_string(keys[i].step) + " and " +
            std::to_string(keys[i + 1].step) + ")";
    // Between two orbit keyframes: the point of the interpolated orbit, placed as a static one
    if (p.on_orbit) {
      if (!is_finite(p.orbit))
        res.fail("camera.keyframes " + where + ": the orbit (azimuth, elevation, distance) " + vec_text(p.orbit) +
                 " is not finite: the keyframes' orbit values are too far apart to interpolate (allowed: values "
                 "whose differences are finite doubles)");
      p.position = resolve_point(PointSpec::on_orbit(p.orbit.x, p.orbit.y, p.orbit.z), b, spec.camera.up);
    }
    p.position = res.point("camera.keyframes " + where + ": position", p.position);
    p.look_at = res.point("camera.keyframes " + where + ": look_at", p.look_at);
  }
  // The camera core can build: a view direction, not along up (core's own test)
  const Vec3 view = p.look_at - p.position;
  if (!(glm::length(view) > 0.0))
    res.fail("camera.keyframes " + where + ": position " + vec_text(p.position) +
             " equals look_at (allowed: keyframes between which the camera never reaches the point it looks at)");
  if (glm::length(glm::cross(glm::normalize(view), glm::normalize(spec.camera.up))) < 1e-9)
    res.fail("camera.keyframes " + where + ": the view direction from " + vec_text(p.position) + " to " +
             vec_text(p.look_at) + " is parallel to camera.up " + vec_text(spec.camera.up) +
             " (allowed: a view that is not straight along up)");
  return p;
}

}  // namespace

std::pair<double, double> resolve_range(const RangeSpec& r, std::pair<double, double> auto_range) {
  if (!r.automatic) return {r.lo, r.hi};
  auto [lo, hi] = auto_range;
  if (!(lo < hi)) {
    // A constant (or empty) field: widen so that u is well defined, the value mapping to 0.5
    // (by 0.5 each way; by 2^-40 |mid| where 0.5 is below the rounding of huge values).
    const double mid = lo == hi ? lo : 0.5 * (lo + hi);
    const double half = std::max(0.5, std::fabs(mid) * 0x1p-40);
    if (!std::isfinite(mid + half)) return {mid - 2.0 * half, mid};  // at the top of the range
    if (!std::isfinite(mid - half)) return {mid, mid + 2.0 * half};
    return {mid - half, mid + half};
  }
  return {lo, hi};
}

TransferFunction build_transfer_function(const TransferFunctionSpec& spec, std::pair<double, double> auto_range) {
  TransferFunction tf;
  std::tie(tf.lo, tf.hi) = resolve_range(spec.range, auto_range);
  tf.density_scale = spec.density_scale;
  tf.opacity = to_scalar_tf(spec.opacity);
  if (spec.diffuse.present()) tf.diffuse = to_color_tf(spec.diffuse);
  if (spec.specular.present()) tf.specular = to_color_tf(spec.specular);
  if (!spec.roughness.empty()) tf.roughness = to_scalar_tf(spec.roughness);
  if (spec.emission.present()) tf.emission = to_color_tf(spec.emission);
  return tf;
}

double resolve_density_scale(const TransferFunctionSpec& tf, const Bounds& data_bounds) {
  if (!tf.density_relative) return tf.density_scale;
  const double diagonal = glm::length(data_bounds.hi - data_bounds.lo);
  const double scale = tf.density_scale / diagonal;
  if (!(diagonal > 0.0) || !std::isfinite(scale))
    throw std::invalid_argument("transfer_function.density_scale {optical_depth: " + format_number(tf.density_scale) +
                                "} is relative to the data's diagonal, but the data's bounds " +
                                vec_text(data_bounds.lo) + " to " + vec_text(data_bounds.hi) + " have a diagonal of " +
                                format_number(diagonal) +
                                " (allowed: data with 2 or more vertices along some axis, or a number: the "
                                "extinction per world unit)");
  return scale;
}

std::shared_ptr<const Image> load_envmap(const BackgroundSpec& bg) {
  if (bg.type != BackgroundType::EnvMap) return nullptr;
  return std::make_shared<const Image>(read_exr(bg.file));
}

SceneDesc build_scene(const RenderSpec& spec, const Bounds& data_bounds, std::pair<double, double> auto_range,
                      const VolumeGeometry& geom, std::int64_t step) {
  return build_scene(spec, data_bounds, auto_range, geom, load_envmap(spec.background), step);
}

SceneDesc build_scene(const RenderSpec& spec, const Bounds& data_bounds, std::pair<double, double> auto_range,
                      const VolumeGeometry& geom, std::shared_ptr<const Image> envmap, std::int64_t step) {
  SceneDesc s;
  s.geometry = geom;
  // The data bounds first: every relative point and size is resolved against them
  if (!is_finite(data_bounds.lo) || !is_finite(data_bounds.hi) || !is_finite(data_bounds.hi - data_bounds.lo) ||
      !std::isfinite(data_bounds.radius()))
    throw std::invalid_argument("volume.spacing " + vec_text(geom.spacing) + " with volume.origin " +
                                vec_text(geom.origin) +
                                " makes the data bounds overflow (their corner or diagonal is not finite)");
  s.tf = build_transfer_function(spec.transfer_function, auto_range);

  // Camera; its up also orients every orbit point
  const Vec3 up = spec.camera.up;
  // (a spacing outside its range is prepare()'s error to report, not the camera's). The
  // uniform axes' smallest spacing: a rectilinear axis' spacing is not its intervals, and its
  // smallest interval needs the field's dims, so prepare() checks it exactly (this check is
  // then the looser one, never refusing what prepare accepts; none if every axis is rectilinear)
  double h = INFINITY;
  for (int a = 0; a < 3; ++a)
    if (!geom.coords[a]) h = std::min(h, geom.spacing[a]);
  const Resolver res{spec.name, h >= kMinSpacing && h <= kMaxSpacing ? kMaxCoordinateVoxels * h : INFINITY};

  // Extinction relative to the data's diagonal, when the TF says so
  try {
    s.tf.density_scale = resolve_density_scale(spec.transfer_function, data_bounds);
  } catch (const std::invalid_argument& e) {
    res.fail(e.what());
  }
  if (spec.camera.keyframes.empty()) {
    const double fit_radii = fit_distance(spec.camera.fov, spec.image.width, spec.image.height);
    res.orbit_extent("camera.position", spec.camera.position, data_bounds);
    s.camera.position = res.point(
        "camera.position",
        resolve_point(res.at_step("camera.position", spec.camera.position, step), data_bounds, up, fit_radii));
    s.camera.look_at = res.point(
        "camera.look_at", resolve_point(res.at_step("camera.look_at", spec.camera.look_at, step), data_bounds, up));
    s.camera.fov_deg = spec.camera.fov;
  } else {
    const CameraPose p = keyframed_pose(res, spec, data_bounds, step);
    s.camera.position = p.position;
    s.camera.look_at = p.look_at;
    s.camera.fov_deg = p.fov;
  }
  s.camera.up = up;
  s.camera.aperture = spec.camera.aperture;
  s.camera.focus_distance = spec.camera.focus_distance;

  // Lights: the checks every kind shares, then its own points and lengths
  for (std::size_t i = 0; i < spec.lights.size(); ++i) {
    const LightFrame f{res, data_bounds, up, step, "lights[" + std::to_string(i) + "]."};
    s.lights.push_back(std::visit(
        [&](const auto& l) -> LightDesc {
          const Color radiance = l.color * l.intensity;
          if (!is_finite(radiance) || std::max({radiance.x, radiance.y, radiance.z}) > kMaxRadiance)
            throw std::invalid_argument("render \"" + spec.name + "\": " + f.key + "intensity " +
                                        format_number(l.intensity) + " times color " + vec_text(l.color) +
                                        " is a radiance above 1e30 (pixels would overflow float32)");
          res.orbit_extent(f.key + "position", l.position, data_bounds);
          return resolve_light(l, f, radiance);
        },
        spec.lights[i]));
  }

  // Background
  const BackgroundSpec& b = spec.background;
  s.background.type = b.type;
  s.background.color = b.color;
  s.background.top = b.top;
  s.background.middle = b.middle;
  s.background.bottom = b.bottom;
  s.background.up = b.up;
  s.background.intensity = b.intensity;
  s.background.visible = b.visible;
  if (b.type == BackgroundType::EnvMap) {
    if (!envmap) throw std::invalid_argument("render \"" + spec.name + "\": envmap " + b.file + " not loaded");
    s.background.envmap = std::move(envmap);
  }

  s.integrator = spec.integrator.desc;
  s.image = spec.image;
  s.options = build_render_options(spec, GlobalOptions{});
  return s;
}

RenderOptions build_render_options(const RenderSpec& spec, const GlobalOptions& global) {
  RenderOptions o;
  o.seed = spec.integrator.seed;
  o.frame = 0;
  o.tile = spec.integrator.tile;
  o.order = spec.integrator.tile_order;
  o.threads = global.threads;
  return o;
}

}  // namespace tessera::config
