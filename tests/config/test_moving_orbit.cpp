// Moving cameras: an orbit value `{start: S, per_step: D}` is S + D * n at simulation step n.
// The scene built at step n renders bit for bit the image of the plain orbit at S + D * n; bad
// values are refused when loading (with file:line:col) or, where only the step decides, when
// the scene is built; the effective config writes the mapping back.
#include "test_support.h"

#include <tessera/config/build_scene.h>
#include <tessera/number_text.h>
#include <tessera/render.h>

#include <cmath>
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

std::string scene(const std::string& orbit, const std::string& light = "center") {
  return "renders:\n  - name: a\n    image: {width: 24, height: 16, spp: 2}\n    camera: {position: {orbit: " + orbit +
         "}, fov: 40}\n    transfer_function: {range: [0, 1], density_scale: 30, opacity: [[0, 0], [1, 1]]}\n"
         "    lights: [{type: sphere, position: " +
         light + ", radius: {relative: 0.2}, intensity: 3}]\n";
}

const Config& parsed(const std::string& yaml, Config& keep) { return keep = parse_config(yaml, "orbit.yaml", ""); }

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

/// The render's film at `step`, the frame number as the adapter sets it.
std::vector<PixelSums> render_at(const Volume& v, const RenderSpec& r, std::int64_t step) {
  SceneDesc s = build_scene(r, v.bounds(), {0.0, 1.0}, v.geom, step);
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

std::string build_error(const RenderSpec& r, const Bounds& b, std::int64_t step) {
  try {
    build_scene(r, b, {0.0, 1.0}, VolumeGeometry{b.lo, Vec3(0.5)}, step);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a moving orbit at step n renders the plain orbit at S + D * n bit for bit", "[config][orbit]") {
  const Volume v;
  struct Case {
    const char* what;
    double s, d;        // the moving value
    const char* other;  // the other two values, plain
  };
  // Each value moving on its own, then all three (the other values' text is substituted)
  for (const std::int64_t n : {std::int64_t{0}, std::int64_t{3}, std::int64_t{41}, std::int64_t{-7}}) {
    const double az = 10.0 + 1.5 * static_cast<double>(n);
    const double el = 20.0 - 0.75 * static_cast<double>(n);
    const double di = 3.0 + 0.125 * static_cast<double>(n);
    for (int which = 0; which < 4; ++which) {
      INFO("step " << n << ", moving value " << which);
      std::string moving =
          "{azimuth: " + std::string(which == 0 || which == 3 ? "{start: 10, per_step: 1.5}" : "10") +
          ", elevation: " + (which == 1 || which == 3 ? "{start: 20, per_step: -0.75}" : std::string("20")) +
          ", distance: " + (which == 2 || which == 3 ? "{start: 3, per_step: 0.125}" : "3") + "}";
      const std::string plain = "{azimuth: " + format_number(which == 0 || which == 3 ? az : 10.0) +
                                ", elevation: " + format_number(which == 1 || which == 3 ? el : 20.0) +
                                ", distance: " + format_number(which == 2 || which == 3 ? di : 3.0) + "}";
      Config cm, cp;
      const RenderSpec& rm = parsed(scene(moving), cm).renders[0];
      const RenderSpec& rp = parsed(scene(plain), cp).renders[0];
      REQUIRE(rm.camera.position.moves());
      REQUIRE_FALSE(rp.camera.position.moves());
      const SceneDesc sm = build_scene(rm, v.bounds(), {0.0, 1.0}, v.geom, n);
      const SceneDesc sp = build_scene(rp, v.bounds(), {0.0, 1.0}, v.geom, n);
      CHECK(sm.camera.position == sp.camera.position);
      CHECK(same_bits(render_at(v, rm, n), render_at(v, rp, n)));
    }
  }
  // distance: fit with a turning azimuth: the fit distance, the azimuth of the step
  Config cm, cp;
  const RenderSpec& rm =
      parsed(scene("{azimuth: {start: -30, per_step: 2}, elevation: 15, distance: fit}"), cm).renders[0];
  const RenderSpec& rp = parsed(scene("{azimuth: 30, elevation: 15, distance: fit}"), cp).renders[0];
  CHECK(same_bits(render_at(v, rm, 30), render_at(v, rp, 30)));
  // A light on a moving orbit moves with the step too
  Config lm, lp;
  const RenderSpec& lrm =
      parsed(scene("{azimuth: 0, distance: 3}", "{orbit: {azimuth: {start: 0, per_step: 9}, distance: 2}}"), lm)
          .renders[0];
  const RenderSpec& lrp =
      parsed(scene("{azimuth: 0, distance: 3}", "{orbit: {azimuth: 90, distance: 2}}"), lp).renders[0];
  CHECK(same_bits(render_at(v, lrm, 10), render_at(v, lrp, 10)));
  // ... and a moving orbit does move: step 0 differs from step 10
  CHECK_FALSE(same_bits(render_at(v, lrm, 0), render_at(v, lrm, 10)));
}

TEST_CASE("orbit values: plain numbers and {start, per_step}, the keys' extremes", "[config][orbit]") {
  Config c;
  const OrbitSpec& o = parsed(scene("{azimuth: {start: 0, per_step: 1.5}, elevation: {start: -90, per_step: 1e6}, "
                                    "distance: {start: 0, per_step: -1e6}}"),
                              c)
                           .renders[0]
                           .camera.position.orbit;
  CHECK(o.azimuth == OrbitValue(0.0, 1.5));
  CHECK(o.elevation == OrbitValue(-90.0, 1e6));
  CHECK(o.distance == OrbitValue(0.0, -1e6));
  // per_step 0 is a value that stays, as the plain number
  Config z;
  const PointSpec& p = parsed(scene("{azimuth: {start: 5, per_step: 0}, distance: 2}"), z).renders[0].camera.position;
  CHECK_FALSE(p.moves());
  CHECK(p.orbit.azimuth == 5.0);
  // The value at step n is S + D * n, exactly S when D is 0, at the ends of the step's range
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();
  CHECK(OrbitValue(7.0).at(kMax) == 7.0);
  CHECK(OrbitValue(-0.0).at(kMin) == 0.0);
  CHECK(std::signbit(OrbitValue(-0.0).at(3)));
  CHECK(OrbitValue(1.0, 1e6).at(kMax) == 1.0 + 1e6 * static_cast<double>(kMax));
  CHECK(std::isfinite(OrbitValue(-std::numeric_limits<double>::max(), -1e6).at(kMax)));

  // Azimuth wraps: any finite value at any step builds, even at the last step
  const Bounds b{Vec3(0.0), Vec3(2.0)};
  Config w;
  const RenderSpec& rw = parsed(scene("{azimuth: {start: 0, per_step: 1e6}, distance: 2}"), w).renders[0];
  CHECK_NOTHROW(build_scene(rw, b, {0.0, 1.0}, VolumeGeometry{b.lo, Vec3(0.5)}, kMax));
  CHECK_NOTHROW(build_scene(rw, b, {0.0, 1.0}, VolumeGeometry{b.lo, Vec3(0.5)}, kMin));
}

TEST_CASE("a moving orbit that leaves its key's range at a step is a clear per-call error", "[config][orbit]") {
  const Bounds b{Vec3(0.0), Vec3(2.0)};
  Config c;
  const RenderSpec& el = parsed(scene("{elevation: {start: 20, per_step: 1.5}, distance: 2}"), c).renders[0];
  CHECK(build_error(el, b, 46).empty());  // 89
  const std::string up = build_error(el, b, 50);
  CHECK_THAT(up,
             Contains("render \"a\": camera.position: orbit elevation {start: 20, per_step: 1.5} is 95 at step 50"));
  CHECK_THAT(up, Contains("allowed: a number in [-90, 90]"));
  CHECK_THAT(build_error(el, b, -74), Contains("is -91 at step -74"));
  CHECK_THAT(build_error(el, b, std::numeric_limits<std::int64_t>::max()), Contains("orbit elevation"));

  Config d;
  const RenderSpec& di = parsed(scene("{distance: {start: 2, per_step: -0.5}}"), d).renders[0];
  CHECK(build_error(di, b, 3).empty());
  CHECK_THAT(build_error(di, b, 5), Contains("orbit distance {start: 2, per_step: -0.5} is -0.5 at step 5 (allowed: "
                                             "a number >= 0)"));
  // A distance that stays >= 0 but leaves the world at a huge step: the resolved point's check
  Config h;
  const RenderSpec& huge = parsed(scene("{distance: {start: 2, per_step: 1e6}}"), h).renders[0];
  CHECK(build_error(huge, b, 1000).empty());
  CHECK_THAT(build_error(huge, b, std::numeric_limits<std::int64_t>::max()),
             Contains("render \"a\": camera.position [") && Contains("lies beyond 2^40 smallest spacings"));
  // A light's orbit names the light
  Config l;
  const RenderSpec& light =
      parsed(scene("{distance: 3}", "{orbit: {elevation: {start: 0, per_step: -10}, distance: 2}}"), l).renders[0];
  CHECK_THAT(build_error(light, b, 10), Contains("lights[0].position: orbit elevation"));
}

TEST_CASE("bad orbit values are refused on load with file:line:col", "[config][orbit]") {
  const auto err = [](const std::string& orbit) { return config_error(scene(orbit)); };
  const std::string unknown = err("{azimuth: {start: 0, per_step: 1, speed: 2}, distance: 2}");
  CHECK_THAT(unknown, Contains("scene.yaml:4:"));
  CHECK_THAT(unknown, Contains("speed"));
  CHECK_THAT(unknown, Contains("unknown key (allowed: start, per_step)"));
  const std::string no_start = err("{azimuth: {per_step: 1}, distance: 2}");
  CHECK_THAT(no_start, Contains("scene.yaml:4:"));
  CHECK_THAT(no_start, Contains("start"));
  CHECK_THAT(no_start, Contains("missing required key"));
  CHECK_THAT(err("{azimuth: {start: 1}, distance: 2}"), Contains("per_step"));
  CHECK_THAT(err("{azimuth: {start: 0, per_step: .inf}, distance: 2}"), Contains(".inf is not a number"));
  CHECK_THAT(err("{azimuth: {start: 0, per_step: .nan}, distance: 2}"), Contains(".nan is not a number"));
  CHECK_THAT(err("{azimuth: {start: 0, per_step: 1e999}, distance: 2}"), Contains("per_step: 1e999 is not"));
  CHECK_THAT(err("{azimuth: {start: 0, per_step: 1000001}, distance: 2}"), Contains("out of range [-1e+06, 1e+06]"));
  CHECK_THAT(err("{azimuth: {start: 0, per_step: -1e7}, distance: 2}"), Contains("out of range"));
  CHECK_THAT(err("{azimuth: {start: .inf, per_step: 1}, distance: 2}"), Contains("start: .inf is not a number"));
  CHECK_THAT(err("{azimuth: {start: 0, per_step: fast}, distance: 2}"), Contains("not a number"));
  CHECK_THAT(err("{azimuth: {start: 0, per_step: [1]}, distance: 2}"), Contains("per_step"));
  CHECK_THAT(err("{azimuth: {}, distance: 2}"), Contains("start"));
  // start within the key's range, as the plain number
  CHECK_THAT(err("{elevation: {start: 91, per_step: -1}, distance: 2}"), Contains("out of range [-90, 90]"));
  CHECK_THAT(err("{distance: {start: -1, per_step: 1}}"), Contains("out of range (>= 0)"));
  // distance: fit is a word; it does not move
  const std::string fit = err("{distance: {start: fit, per_step: 0.1}}");
  CHECK_THAT(fit, Contains("scene.yaml:4:"));
  CHECK_THAT(fit, Contains("distance: fit cannot move per step"));
  CHECK_THAT(err("{distance: [1, 2]}"), Contains("{start: S, per_step: D}"));
}

TEST_CASE("the effective config writes a moving orbit back as {start, per_step}", "[config][orbit]") {
  const std::string yaml = scene("{azimuth: {start: 0, per_step: 1.5}, elevation: {start: 20, per_step: 0}, distance: "
                                 "{start: 2.5, per_step: -0.001}}",
                                 "{orbit: {azimuth: {start: 45, per_step: -3}, distance: 2}}");
  const Config a = parse_config(yaml, "a.yaml", "");
  const std::string text = to_yaml(a);
  INFO(text);
  CHECK_THAT(text, Contains("azimuth: {start: 0, per_step: 1.5}"));
  CHECK_THAT(text, Contains("elevation: 20,"));  // per_step 0: the plain number
  CHECK_THAT(text, Contains("distance: {start: 2.5, per_step: -0.001}"));
  CHECK_THAT(text, Contains("azimuth: {start: 45, per_step: -3}"));
  const Config b = parse_config(text, "b.yaml", "");
  CHECK(b.renders[0].camera.position.orbit.azimuth == a.renders[0].camera.position.orbit.azimuth);
  CHECK(b.renders[0].camera.position.orbit.elevation == a.renders[0].camera.position.orbit.elevation);
  CHECK(b.renders[0].camera.position.orbit.distance == a.renders[0].camera.position.orbit.distance);
  CHECK(to_yaml(b) == text);

  // With distance: fit the word stays beside a moving azimuth
  const Config f =
      parse_config(scene("{azimuth: {start: 0.1, per_step: 0.3}, elevation: 20, distance: fit}"), "f.yaml", "");
  const std::string ft = to_yaml(f);
  CHECK_THAT(ft, Contains("{orbit: {azimuth: {start: 0.1, per_step: 0.3}, elevation: 20, distance: fit}}"));
  CHECK(to_yaml(parse_config(ft, "g.yaml", "")) == ft);
}

TEST_CASE("a moving orbit at huge steps: a finite camera or a clear error, never NaN", "[config][orbit]") {
  // Each key at its largest per_step, at steps up to 2^62 and the ends of int64: S + D * n is
  // finite (|D n| <= 1e6 * 2^63), so the azimuth builds (it wraps), the elevation and the
  // distance leave their range or the world with a message naming the value and the step
  const Bounds b{Vec3(0.0), Vec3(2.0)};
  constexpr std::int64_t kBig = std::int64_t{1} << 62;
  for (const std::int64_t n :
       {kBig, -kBig, std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min()}) {
    INFO("step " << n);
    Config a, e, d;
    const RenderSpec& az = parsed(scene("{azimuth: {start: 0, per_step: 1e6}, distance: 2}"), a).renders[0];
    const SceneDesc s = build_scene(az, b, {0.0, 1.0}, VolumeGeometry{b.lo, Vec3(0.5)}, n);
    CHECK(is_finite(s.camera.position));
    CHECK(glm::length(s.camera.position - b.center()) == Approx(2.0 * b.radius()));
    const RenderSpec& el = parsed(scene("{elevation: {start: 0, per_step: -1e6}, distance: 2}"), e).renders[0];
    CHECK_THAT(build_error(el, b, n), Contains("orbit elevation {start: 0, per_step: -1e+06} is ") &&
                                          Contains("at step " + std::to_string(n)));
    const RenderSpec& di = parsed(scene("{distance: {start: 0, per_step: 1e6}}"), d).renders[0];
    const std::string msg = build_error(di, b, n);
    CHECK_THAT(msg, Contains(n > 0 ? "lies beyond 2^40 smallest spacings" : "orbit distance {start: 0, per_step: "));
  }
  // The largest azimuths (their radians overflow) wrap exactly modulo 360: a finite camera
  for (const double az : {1.7e308, -std::numeric_limits<double>::max()}) {
    INFO("azimuth " << az);
    const Vec3 d = orbit_direction(OrbitSpec{az, 10.0, 1.0}, Vec3(0, 0, 1));
    CHECK(is_finite(d));
    CHECK(d == orbit_direction(OrbitSpec{std::fmod(az, 360.0), 10.0, 1.0}, Vec3(0, 0, 1)));
  }
}
