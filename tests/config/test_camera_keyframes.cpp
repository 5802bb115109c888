// Camera keyframes: `camera: {keyframes: [{step, position, look_at, fov}, ...]}`. At a keyframe's
// step the camera is that keyframe's static camera bit for bit; between two keyframes it is
// their interpolation (linear, or a Catmull-Rom spline with `interpolation: smooth`); outside
// them it holds. Bad keyframes are refused on load with file:line:col; a pose that makes no
// camera at some step fails that build with the step.
#include "test_support.h"

#include <tessera/config/build_scene.h>
#include <tessera/config/camera_keyframes.h>
#include <tessera/render.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace tessera;
using namespace tessera::config;
using Catch::Matchers::Contains;
using tessera::config::test::config_error;

namespace {

constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();

/// A one-render config whose camera is `camera` (the text inside `camera: {...}`).
std::string scene(const std::string& camera) {
  return "renders:\n  - name: a\n    image: {width: 24, height: 16, spp: 2}\n    camera: {" + camera +
         "}\n    transfer_function: {range: [0, 1], density_scale: 30, opacity: [[0, 0], [1, 1]]}\n"
         "    lights: [{type: sphere, position: [3, 1, 4], radius: 0.3, intensity: 3}]\n";
}

RenderSpec render_of(const std::string& camera) { return parse_config(scene(camera), "keys.yaml", "").renders[0]; }

/// A small field (a ramp along x with a bump), its geometry and bounds.
struct Volume {
  static constexpr int n = 8;
  std::vector<float> field;
  VolumeGeometry geom{Vec3(-1.0, 0.0, 0.5), Vec3(0.25, 0.3, 0.2)};
  Volume() {
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) field.push_back(static_cast<float>(x) / n * (y > 2 && z < 5 ? 1.0f : 0.4f));
  }
  FieldView view() const { return FieldView::contiguous(field.data(), DType::Float32, n, n, n); }
  Bounds bounds() const { return field_bounds(view(), geom); }
};

SceneDesc scene_at(const Volume& v, const RenderSpec& r, std::int64_t step) {
  return build_scene(r, v.bounds(), {0.0, 1.0}, v.geom, step);
}

/// The render's film at `step`, the frame number as the adapter sets it.
std::vector<PixelSums> render_at(const Volume& v, const RenderSpec& r, std::int64_t step) {
  SceneDesc s = scene_at(v, r, step);
  s.options.frame = static_cast<std::uint64_t>(step);
  const PreparedScene ps = prepare(v.view(), s);
  Film film(s.image.width, s.image.height);
  RenderStats stats;
  render(ps, film, stats);
  return film.pixels();
}

bool same_bits(const std::vector<PixelSums>& a, const std::vector<PixelSums>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(PixelSums)) == 0;
}

bool same_camera(const CameraDesc& a, const CameraDesc& b) {
  return a.position == b.position && a.look_at == b.look_at && a.up == b.up && a.fov_deg == b.fov_deg &&
         a.aperture == b.aperture && a.focus_distance == b.focus_distance;
}

std::string build_error(const RenderSpec& r, std::int64_t step) {
  const Volume v;
  try {
    scene_at(v, r, step);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// Three keyframes: an absolute point, an orbit, an orbit framed with distance: fit
const std::string kThree =
    "keyframes: [{step: 10, position: [2, -3, 2], look_at: [0, 1, 1], fov: 30}, "
    "{step: 20, position: {orbit: {azimuth: 80, elevation: 10, distance: 3}}, fov: 50}, "
    "{step: 40, position: {orbit: {azimuth: 150, elevation: 40, distance: fit}}, look_at: center, fov: 35}], "
    "up: [0, 0, 1], aperture: 0.01";
// The static camera of each keyframe
const char* kStatic[] = {"position: [2, -3, 2], look_at: [0, 1, 1], fov: 30, up: [0, 0, 1], aperture: 0.01",
                         "position: {orbit: {azimuth: 80, elevation: 10, distance: 3}}, fov: 50, up: [0, 0, 1], "
                         "aperture: 0.01",
                         "position: {orbit: {azimuth: 150, elevation: 40, distance: fit}}, look_at: center, fov: 35, "
                         "up: [0, 0, 1], aperture: 0.01"};

}  // namespace

TEST_CASE("a keyframed camera at a keyframe's step is that keyframe's static camera bit for bit",
          "[config][keyframes]") {
  const Volume v;
  for (const char* mode : {"linear", "smooth"}) {
    const RenderSpec keyed = render_of(kThree + ", interpolation: " + mode);
    REQUIRE(keyed.camera.keyframes.size() == 3);
    const std::int64_t steps[] = {10, 20, 40};
    for (int k = 0; k < 3; ++k) {
      INFO(mode << ", keyframe " << k);
      const RenderSpec plain = render_of(kStatic[k]);
      CHECK(same_camera(scene_at(v, keyed, steps[k]).camera, scene_at(v, plain, steps[k]).camera));
      CHECK(same_bits(render_at(v, keyed, steps[k]), render_at(v, plain, steps[k])));
    }
  }
  // Outside the keyframes the camera holds: the first before it, the last after it, to the
  // ends of the step range
  const RenderSpec keyed = render_of(kThree);
  const RenderSpec first = render_of(kStatic[0]);
  const RenderSpec last = render_of(kStatic[2]);
  for (const std::int64_t n : {kMin, std::int64_t{-5}, std::int64_t{0}, std::int64_t{9}})
    CHECK(same_camera(scene_at(v, keyed, n).camera, scene_at(v, first, n).camera));
  for (const std::int64_t n : {std::int64_t{41}, std::int64_t{1000}, std::int64_t{1} << 62, kMax})
    CHECK(same_camera(scene_at(v, keyed, n).camera, scene_at(v, last, n).camera));
  CHECK(same_bits(render_at(v, keyed, 77), render_at(v, last, 77)));
  // ... and between keyframes it moves: each step's image differs from the next
  CHECK_FALSE(same_bits(render_at(v, keyed, 12), render_at(v, keyed, 13)));
}

TEST_CASE("between two keyframes the camera is their interpolation", "[config][keyframes]") {
  const Volume v;
  const Bounds b = v.bounds();
  const RenderSpec keyed = render_of(kThree);
  const CameraDesc c10 = scene_at(v, keyed, 10).camera;
  const CameraDesc c20 = scene_at(v, keyed, 20).camera;
  const CameraDesc c40 = scene_at(v, keyed, 40).camera;
  // Linear: halfway is the midpoint of position, look_at and fov; a quarter is a quarter
  const CameraDesc c15 = scene_at(v, keyed, 15).camera;
  CHECK(c15.position == 0.5 * c10.position + 0.5 * c20.position);
  CHECK(c15.look_at == 0.5 * c10.look_at + 0.5 * c20.look_at);
  CHECK(c15.look_at == 0.5 * Vec3(0, 1, 1) + 0.5 * b.center());
  CHECK(c15.fov_deg == 40.0);
  // Between two orbit keyframes the camera stays on the orbit: azimuth, elevation and distance
  // (fit: that keyframe's fit distance) interpolated, placed as a static orbit is
  const CameraDesc c25 = scene_at(v, keyed, 25).camera;
  const double fit = fit_distance(35.0, 24, 16);
  CHECK(c25.position == resolve_point(PointSpec::on_orbit(0.75 * 80.0 + 0.25 * 150.0, 0.75 * 10.0 + 0.25 * 40.0,
                                                          0.75 * 3.0 + 0.25 * fit),
                                      b, Vec3(0, 0, 1)));
  CHECK(c25.position != 0.75 * c20.position + 0.25 * c40.position);
  CHECK(c25.fov_deg == 0.75 * 50.0 + 0.25 * 35.0);
  CHECK(c25.up == Vec3(0, 0, 1));
  CHECK(c25.aperture == 0.01);

  // Smooth: through the same keyframes, on a C1 curve that is not the straight line, whose
  // velocity at keyframe 20 is the same from both sides (Catmull-Rom); the fov stays within
  // its two keyframes
  const RenderSpec smooth = render_of(kThree + ", interpolation: smooth");
  const CameraDesc s15 = scene_at(v, smooth, 15).camera;
  CHECK(glm::length(s15.position - c15.position) > 1e-3);
  CHECK(s15.fov_deg >= 30.0);
  CHECK(s15.fov_deg <= 50.0);
  const double eps = 1e-3;  // steps are integers; the pose is a function of t, sampled by hand
  PoseWindow w;
  w.has_before = w.has_after = true;
  w.pose[0] = {c10.position, c10.look_at, 30.0};
  w.pose[1] = {c20.position, c20.look_at, 50.0};
  w.pose[2] = {c40.position, c40.look_at, 35.0};
  w.step[0] = 10;
  w.step[1] = 20;
  w.step[2] = 40;
  PoseWindow before = w;  // the segment 10 -> 20
  before.has_before = false;
  before.pose[0] = {};
  before.pose[1] = w.pose[0];
  before.pose[2] = w.pose[1];
  before.pose[3] = w.pose[2];
  before.step[0] = 0;
  before.step[1] = 10;
  before.step[2] = 20;
  before.step[3] = 40;
  w.has_after = false;
  // Velocity per step on each side of step 20
  const Vec3 v_in =
      (interpolate_pose(CameraInterpolation::Smooth, before, 1.0 - eps).position - c20.position) / (-eps * 10.0);
  const Vec3 v_out = (interpolate_pose(CameraInterpolation::Smooth, w, eps).position - c20.position) / (eps * 20.0);
  CHECK(glm::length(v_in - v_out) < 1e-2 * glm::length(v_out));
  // The tangent there is (p40 - p10) / 30 per step
  CHECK(glm::length(v_out - (c40.position - c10.position) / 30.0) < 1e-2 * glm::length(v_out));
  // The build uses the same function
  const KeyframeSpan span = keyframe_span(std::vector<std::int64_t>{10, 20, 40}, 15);
  CHECK(span.i == 0);
  CHECK(span.t == 0.5);
  CHECK(s15.position == interpolate_pose(CameraInterpolation::Smooth, before, 0.5).position);
  // Two keyframes only: smooth is the straight line
  const std::string two = "keyframes: [{step: 0, position: [3, 0, 1]}, {step: 8, position: [0, 3, 2], fov: 60}]";
  const RenderSpec l2 = render_of(two), s2 = render_of(two + ", interpolation: smooth");
  for (const std::int64_t n : {1, 3, 4, 7}) {
    const CameraDesc a = scene_at(v, l2, n).camera, c = scene_at(v, s2, n).camera;
    CHECK(glm::length(a.position - c.position) < 1e-12);
    CHECK(a.fov_deg == Approx(c.fov_deg).epsilon(1e-12));
  }
}

TEST_CASE("between two orbit keyframes the camera turns along the orbit", "[config][keyframes]") {
  const Volume v;
  for (const char* mode : {"linear", "smooth"}) {
    INFO(mode);
    // Halfway between azimuth 0 and 90 (elevation 10 to 30, distance 2 to 4): the static orbit
    // at 45, 20, 3, bit for bit, image included
    const RenderSpec keyed =
        render_of("keyframes: [{step: 0, position: {orbit: {azimuth: 0, elevation: 10, distance: 2}}}, "
                  "{step: 10, position: {orbit: {azimuth: 90, elevation: 30, distance: 4}}}], interpolation: " +
                  std::string(mode));
    const RenderSpec half = render_of("position: {orbit: {azimuth: 45, elevation: 20, distance: 3}}");
    CHECK(same_camera(scene_at(v, keyed, 5).camera, scene_at(v, half, 5).camera));
    CHECK(same_bits(render_at(v, keyed, 5), render_at(v, half, 5)));
    // Azimuth 0 to 360 is a full turn: at the middle the camera is on the other side
    const RenderSpec turn = render_of(
        "keyframes: [{step: 0, position: {orbit: {azimuth: 0, distance: fit}}}, {step: 100, position: {orbit: "
        "{azimuth: 360, distance: fit}}}], interpolation: " +
        std::string(mode));
    const Vec3 c = v.bounds().center();
    const Vec3 p0 = scene_at(v, turn, 0).camera.position - c;
    const Vec3 p50 = scene_at(v, turn, 50).camera.position - c;
    CHECK(glm::dot(glm::normalize(p0), glm::normalize(p50)) == Approx(-1.0));
    CHECK(glm::length(p50) == Approx(glm::length(p0)));
  }
  // Smooth with three orbit keyframes: the elevation overshoots nowhere (clamped to each
  // segment's keyframes), the azimuth follows the spline
  const RenderSpec three = render_of(
      "keyframes: [{step: 0, position: {orbit: {azimuth: 0, elevation: 0, distance: 3}}}, {step: 10, position: {orbit: "
      "{azimuth: 90, elevation: 80, distance: 3}}}, {step: 20, position: {orbit: {azimuth: 100, elevation: 80, "
      "distance: 3}}}], interpolation: smooth");
  const Vec3 c = v.bounds().center();
  for (int n = 0; n <= 20; ++n) {
    const Vec3 d = glm::normalize(scene_at(v, three, n).camera.position - c);
    CHECK(std::asin(d.z) * 180.0 / kPi <= 80.0 + 1e-9);
  }
  // An orbit keyframe next to a point keyframe: that segment is a straight line
  const RenderSpec mixed =
      render_of("keyframes: [{step: 0, position: {orbit: {azimuth: 0, distance: 2}}}, {step: 4, position: [9, 9, 9]}]");
  const CameraDesc m0 = scene_at(v, mixed, 0).camera, m4 = scene_at(v, mixed, 4).camera;
  CHECK(scene_at(v, mixed, 2).camera.position == 0.5 * m0.position + 0.5 * m4.position);
}

TEST_CASE("keyframe_span: exact at the ends of the step range", "[config][keyframes]") {
  const std::vector<std::int64_t> one{7};
  for (const std::int64_t n : {kMin, std::int64_t{7}, kMax}) {
    const KeyframeSpan s = keyframe_span(one, n);
    CHECK(s.i == 0);
    CHECK(s.t == 0.0);
  }
  // Keyframes at the two ends of int64: the difference passes INT64_MAX and is still right
  const std::vector<std::int64_t> ends{kMin, kMax};
  CHECK(keyframe_span(ends, kMin).t == 0.0);
  CHECK(keyframe_span(ends, kMax).i == 1);
  CHECK(keyframe_span(ends, kMax).t == 0.0);
  CHECK(keyframe_span(ends, -1).t == 0.5);  // 2^63 - 1 of 2^64 - 1, rounded
  CHECK(keyframe_span(ends, 0).t == 0.5);
  const KeyframeSpan near_end = keyframe_span(ends, kMax - 1);
  CHECK(near_end.i == 0);
  CHECK(near_end.t <= 1.0);
  // A keyframed camera at steps near 2^62 and at the ends: finite, the keyframes' own pose
  const RenderSpec r =
      render_of("keyframes: [{step: -9223372036854775808, position: [3, 0, 1]}, {step: 4611686018427387904, position: "
                "[0, 3, 2]}, "
                "{step: 9223372036854775807, position: {orbit: {azimuth: 1e300, elevation: -89, distance: 1e6}}}]");
  const Volume v;
  for (const std::int64_t n : {kMin, kMin + 1, std::int64_t{0}, std::int64_t{1} << 62, kMax - 1, kMax}) {
    INFO(n);
    const CameraDesc c = scene_at(v, r, n).camera;
    CHECK(is_finite(c.position));
  }
  CHECK(scene_at(v, r, std::int64_t{1} << 62).camera.position == Vec3(0, 3, 2));
}

TEST_CASE("bad keyframes are refused on load with file:line:col", "[config][keyframes]") {
  const auto err = [](const std::string& camera) { return config_error(scene(camera)); };
  // Out of order and duplicated steps: at the offending step
  const std::string order = err("keyframes: [{step: 5, position: [3, 0, 0]}, {step: 2, position: [0, 3, 0]}]");
  CHECK_THAT(order, Contains("scene.yaml:4:"));
  CHECK_THAT(order, Contains("renders[0].camera.keyframes[1].step"));
  CHECK_THAT(order, Contains("keyframe step 2 comes after step 5 (allowed: keyframes in increasing step order, "
                             "each step once)"));
  CHECK_THAT(err("keyframes: [{step: 5, position: [3, 0, 0]}, {step: 5, position: [0, 3, 0]}]"),
             Contains("keyframe step 5 is given twice"));
  // Too few, too many, not a list, not a mapping
  CHECK_THAT(err("keyframes: []"), Contains("keyframes"));
  CHECK_THAT(err("keyframes: []"), Contains("list has 0 elements (allowed: a list of keyframes, each {step: N, "
                                            "position: point, look_at: point, fov: degrees}, in increasing step "
                                            "order, 1 to 4096 elements)"));
  CHECK_THAT(err("keyframes: {step: 0, position: [3, 0, 0]}"), Contains("allowed: a list of keyframes"));
  CHECK_THAT(err("keyframes: [[3, 0, 0]]"), Contains("keyframes[0]"));
  std::string many = "keyframes: [";
  for (int i = 0; i <= 4096; ++i)
    many += (i ? ", " : "") + std::string("{step: ") + std::to_string(i) + ", position: [3, 0, 0]}";
  CHECK_THAT(err(many + "]"), Contains("list has 4097 elements") && Contains("1 to 4096 elements"));
  // Missing and unknown keys
  CHECK_THAT(err("keyframes: [{position: [3, 0, 0]}]"), Contains("missing required key"));
  CHECK_THAT(err("keyframes: [{position: [3, 0, 0]}]"), Contains("step"));
  CHECK_THAT(err("keyframes: [{step: 0}]"), Contains("keyframes[0]"));
  CHECK_THAT(err("keyframes: [{step: 0}]"), Contains("position"));
  CHECK_THAT(err("keyframes: [{step: 0, position: [3, 0, 0], up: [0, 1, 0]}]"), Contains("unknown key"));
  // Non-finite and out-of-range values
  CHECK_THAT(err("keyframes: [{step: 0, position: [.inf, 0, 0]}]"), Contains("keyframes[0].position"));
  CHECK_THAT(err("keyframes: [{step: 0, position: [3, 0, 0], look_at: [0, .nan, 0]}]"), Contains("look_at"));
  CHECK_THAT(err("keyframes: [{step: 0, position: [3, 0, 0], fov: .nan}]"), Contains("not a number"));
  CHECK_THAT(err("keyframes: [{step: 0, position: [3, 0, 0], fov: 180}]"), Contains("out of range (0, 180)"));
  CHECK_THAT(err("keyframes: [{step: 0, position: [3, 0, 0], fov: 0}]"), Contains("out of range (0, 180)"));
  CHECK_THAT(err("keyframes: [{step: 1.5, position: [3, 0, 0]}]"), Contains("keyframes[0].step"));
  CHECK_THAT(err("keyframes: [{step: 9223372036854775808, position: [3, 0, 0]}]"), Contains("keyframes[0].step"));
  CHECK_THAT(err("keyframes: [{step: 0, position: {orbit: {elevation: 91, distance: 2}}}]"),
             Contains("out of range [-90, 90]"));
  // position == look_at where it is plain to see
  const std::string same = err("keyframes: [{step: 0, position: [1, 2, 3], look_at: [1, 2, 3]}]");
  CHECK_THAT(same, Contains("keyframes[0].position"));
  CHECK_THAT(same, Contains("keyframe position equals look_at"));
  CHECK_THAT(err("keyframes: [{step: 0, position: center}]"), Contains("keyframe position equals look_at"));
  // Keyframes beside the static camera's own keys
  for (const char* own : {"position: [3, 0, 0]", "look_at: center", "fov: 30"}) {
    const std::string mixed = err(std::string(own) + ", keyframes: [{step: 0, position: [3, 0, 0]}]");
    INFO(own);
    CHECK_THAT(mixed, Contains("scene.yaml:4:"));
    CHECK_THAT(mixed, Contains("beside camera.keyframes (allowed: either position, look_at and fov, or keyframes"));
  }
  CHECK_THAT(err("position: [3, 0, 0], interpolation: smooth"), Contains("this camera has none"));
  CHECK_THAT(err("keyframes: [{step: 0, position: [3, 0, 0]}], interpolation: cubic"),
             Contains("cubic is not allowed (allowed: linear or smooth)"));
  CHECK(err("fov: 30").empty());  // position has a default (render_defaults.h)
  // A keyframe's orbit does not move per step; distance: fit only in position
  CHECK_THAT(err("keyframes: [{step: 0, position: {orbit: {azimuth: {start: 0, per_step: 1}, distance: 2}}}]"),
             Contains("a keyframe's orbit does not move per step"));
  CHECK_THAT(err("keyframes: [{step: 0, position: [3, 0, 0], look_at: {orbit: {distance: fit}}}]"),
             Contains("only camera.position takes it"));
}

TEST_CASE("a keyframed pose that makes no camera fails that step's build, naming it", "[config][keyframes]") {
  // The camera passes through the point it looks at halfway between the keyframes
  const RenderSpec through = render_of(
      "keyframes: [{step: 0, position: [-1, 0, 0], look_at: [0, 0, 0]}, {step: 10, position: [1, 0, 0], look_at: [0, "
      "0, 0]}]");
  CHECK(build_error(through, 4).empty());
  CHECK(build_error(through, 6).empty());
  CHECK_THAT(build_error(through, 5), Contains("render \"a\": camera.keyframes at step 5 (between keyframes 0 and 1, "
                                               "steps 0 and 10): position [0, 0, 0] equals look_at"));
  // ... or looks straight along up
  const RenderSpec along = render_of(
      "keyframes: [{step: 0, position: [0, 0, 3], look_at: [1, 0, 0]}, {step: 2, position: [0, 0, 3], look_at: [-1, "
      "0, 0]}]");
  CHECK_THAT(build_error(along, 1), Contains("is parallel to camera.up [0, 0, 1]"));
  // A keyframe's orbit at distance 0 sits on look_at (center): that keyframe, at its step
  const RenderSpec zero = render_of("keyframes: [{step: 3, position: {orbit: {azimuth: 10, distance: 0}}}]");
  CHECK_THAT(build_error(zero, 3), Contains("camera.keyframes at step 3 (keyframe 0, step 3): position"));
  // Orbit keyframes whose azimuths are finite but whose difference is not: the smooth spline's
  // tangent overflows, a clear error for the steps between them (linear stays finite)
  const std::string huge = "keyframes: [{step: 0, position: {orbit: {azimuth: -1.7e308, distance: 2}}}, {step: 2, "
                           "position: {orbit: {azimuth: 1.7e308, distance: 2}}}, {step: 4, position: {orbit: "
                           "{azimuth: -1.7e308, distance: 2}}}], interpolation: ";
  CHECK(build_error(render_of(huge + "linear"), 1).empty());
  CHECK(build_error(render_of(huge + "smooth"), 2).empty());
  CHECK_THAT(build_error(render_of(huge + "smooth"), 1),
             Contains("camera.keyframes at step 1 (between keyframes 0 and 1, steps 0 and 2): the orbit (azimuth, "
                      "elevation, distance) [") &&
                 Contains("is not finite"));
  // An orbit distance that resolves beyond the representable world names the keyframe
  const RenderSpec far =
      render_of("keyframes: [{step: 0, position: [3, 0, 0]}, {step: 1, position: {orbit: {distance: 1e300}}}]");
  CHECK(build_error(far, 0).empty());
  CHECK_THAT(build_error(far, 1), Contains("camera.keyframes[1].position"));
}

TEST_CASE("the effective config writes keyframes back", "[config][keyframes]") {
  const Config a = parse_config(scene(kThree + ", interpolation: smooth"), "a.yaml", "");
  const std::string text = to_yaml(a);
  INFO(text);
  CHECK_THAT(text, Contains("keyframes:"));
  CHECK_THAT(text, Contains("- {step: 10, position: [2, -3, 2], look_at: [0, 1, 1], fov: 30}"));
  CHECK_THAT(text, Contains("- {step: 40, position: {orbit: {azimuth: 150, elevation: 40, distance: fit}}, look_at: "
                            "center, fov: 35}"));
  CHECK_THAT(text, Contains("interpolation: smooth"));
  const Config b = parse_config(text, "b.yaml", "");
  REQUIRE(b.renders[0].camera.keyframes.size() == 3);
  CHECK(b.renders[0].camera.keyframes[1].position.orbit.azimuth == 80.0);
  CHECK(b.renders[0].camera.interpolation == CameraInterpolation::Smooth);
  CHECK(to_yaml(b) == text);
}

TEST_CASE("the heat demo's movie config loads: a camera turning 3.6 degrees a step", "[config][keyframes]") {
  const Config c = load_config(std::string(TESSERA_TEST_DATA_DIR) + "/../../configs/heat_movie.yaml");
  REQUIRE(c.renders.size() == 1);
  const RenderSpec& r = c.renders[0];
  CHECK(r.camera.position.moves());
  CHECK(r.camera.position.orbit.azimuth == OrbitValue(35.0, 3.6));
  CHECK(r.camera.position.is_fit());
  REQUIRE(r.trigger);
  CHECK(r.trigger->every == 2);
  CHECK_FALSE(c.global.budget > 0.0);  // every trigger renders: the movie has all its frames
}
