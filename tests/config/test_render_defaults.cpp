// `renders: [{field: f}]` alone: the documented defaults (render_defaults.h, docs/config.md
// "The smallest config"), written out by to_yaml, and an extinction relative to the data's
// diagonal, so that the picture does not depend on the data's length unit.
#include "test_support.h"

#include <tessera/config/build_scene.h>
#include <tessera/config/render_defaults.h>
#include <tessera/render.h>

#include <cmath>
#include <variant>
#include <vector>

using namespace tessera;
using namespace tessera::config;
using Catch::Matchers::Contains;
using tessera::config::test::config_error;

namespace {

const char* kMinimal = "renders: [{field: energy}]\n";

/// A field with structure: a soft ball and two denser lumps, in [0, 1], on n^3 vertices.
std::vector<float> lumpy_field(int n) {
  std::vector<float> v(static_cast<std::size_t>(n) * n * n);
  const auto lump = [](double x, double y, double z, double cx, double cy, double cz, double r) {
    const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz);
    return std::exp(-d2 / (r * r));
  };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = i / double(n - 1), y = j / double(n - 1), z = k / double(n - 1);
        const double r = std::sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) + (z - 0.5) * (z - 0.5));
        const double f = 0.4 * std::max(0.0, 1.0 - 2.0 * r) + lump(x, y, z, 0.35, 0.4, 0.6, 0.12) +
                         lump(x, y, z, 0.65, 0.6, 0.4, 0.1);
        v[(static_cast<std::size_t>(k) * n + j) * n + i] = static_cast<float>(std::min(1.0, f));
      }
  return v;
}

/// The image of `spec` over `field` placed with `geom` (bounds and range from the field).
Image render_image(const RenderSpec& spec, const FieldView& view, const VolumeGeometry& geom) {
  const Bounds b = field_bounds(view, geom);
  const SceneDesc s = build_scene(spec, b, *field_range(view), geom);
  const PreparedScene ps = prepare(view, s);
  Film film(s.image.width, s.image.height);
  RenderStats stats;
  render(ps, film, stats);
  return film.resolve();
}

double luminance(const Image& img, std::size_t i) {
  return 0.2126 * img.rgba[4 * i] + 0.7152 * img.rgba[4 * i + 1] + 0.0722 * img.rgba[4 * i + 2];
}

/// Mean |a - b| of the luminance over the mean luminance of a.
double relative_difference(const Image& a, const Image& b) {
  double diff = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < std::size_t(a.width) * a.height; ++i) {
    diff += std::fabs(luminance(a, i) - luminance(b, i));
    sum += luminance(a, i);
  }
  return diff / sum;
}

}  // namespace

TEST_CASE("a render of a field name alone takes the documented defaults", "[config][defaults]") {
  const Config c = parse_config(kMinimal, "minimal.yaml", "");
  REQUIRE(c.renders.size() == 1);
  const RenderSpec& r = c.renders[0];
  CHECK(r.name == "energy");
  CHECK(r.field == "energy");
  CHECK_FALSE(r.trigger);
  CHECK(r.image.width == 512);
  CHECK(r.image.height == 512);
  CHECK(r.image.spp == 16);
  CHECK(r.output.file == "{name}_{step:06d}");
  CHECK(r.output.formats == std::vector<ImageFormat>{ImageFormat::Exr, ImageFormat::Png});

  // Camera: a three-quarter view framed with distance: fit
  const PointSpec& p = r.camera.position;
  REQUIRE(p.kind == PointSpec::Kind::Orbit);
  CHECK(p.orbit.fit);
  CHECK(p.orbit.azimuth.start == 35.0);
  CHECK(p.orbit.elevation.start == 25.0);
  CHECK(r.camera.look_at.kind == PointSpec::Kind::Center);
  CHECK(r.camera.up == Vec3(0, 0, 1));
  CHECK(r.camera.fov == 30.0);

  // Transfer function: auto range, viridis, the opacity ramp, extinction relative to the data
  const TransferFunctionSpec& tf = r.transfer_function;
  CHECK(tf.range.automatic);
  CHECK(tf.density_relative);
  CHECK(tf.density_scale == kDefaultOpticalDepth);
  CHECK(kDefaultOpticalDepth == 16.0);
  REQUIRE(tf.opacity.size() == 3);
  CHECK(tf.opacity[1].u == 0.5);
  CHECK(tf.opacity[1].v == 0.2);
  CHECK(tf.opacity[2].v == 1.0);
  CHECK(tf.diffuse.colormap == "viridis");
  CHECK_FALSE(tf.emission.present());

  // One rect key light placed and sized relative to the data, a dark gradient background
  REQUIRE(r.lights.size() == 1);
  const auto* key = std::get_if<RectLightSpec>(&r.lights[0]);
  REQUIRE(key);
  CHECK(key->position.kind == PointSpec::Kind::Orbit);
  CHECK(key->position.orbit.azimuth.start == -30.0);
  CHECK(key->position.orbit.elevation.start == 50.0);
  CHECK(key->position.orbit.distance.start == 3.0);
  CHECK(key->width.relative);
  CHECK(key->width.value == 1.5);
  CHECK(key->intensity == 60.0);
  CHECK(r.background.type == BackgroundType::Gradient);
  CHECK(r.background.top == Color(0.3, 0.36, 0.5));
  CHECK(r.background.visible);
  CHECK(r.integrator.desc.scattering == Scattering::Single);
}

TEST_CASE("a render that gives its own blocks keeps them, and the per-key defaults", "[config][defaults]") {
  // A given transfer function: no lights, a black background, density_scale 1 per world unit,
  // as before these defaults existed; its opacity alone may be left out
  const Config own = parse_config("renders: [{name: a, transfer_function: {diffuse: magma}}]\n", "a.yaml", "");
  const RenderSpec& a = own.renders[0];
  CHECK(a.lights.empty());
  CHECK(a.background.type == BackgroundType::Constant);
  CHECK(a.background.color == Color(0.0));
  CHECK_FALSE(a.transfer_function.density_relative);
  CHECK(a.transfer_function.density_scale == 1.0);
  CHECK(a.transfer_function.opacity.size() == default_opacity().size());
  CHECK(a.camera.position.is_fit());

  // The default look, but with lights or background given: those are kept
  const Config dark = parse_config("renders: [{field: e, lights: [], background: {type: constant}}]\n", "d.yaml", "");
  CHECK(dark.renders[0].lights.empty());
  CHECK(dark.renders[0].background.type == BackgroundType::Constant);
  CHECK(dark.renders[0].transfer_function.density_relative);

  // A camera without position frames the data; keyframes still replace it
  const Config cam = parse_config("renders: [{field: e, camera: {fov: 45, up: [0, 1, 0]}}]\n", "c.yaml", "");
  CHECK(cam.renders[0].camera.position.is_fit());
  CHECK(cam.renders[0].camera.fov == 45.0);

  // density_scale: auto is {optical_depth: 16}; numbers stay per world unit
  const auto density = [](const std::string& value) {
    const Config d =
        parse_config("renders: [{field: e, transfer_function: {density_scale: " + value + "}}]\n", "t.yaml", "");
    return d.renders[0].transfer_function;
  };
  CHECK(density("auto").density_relative);
  CHECK(density("auto").density_scale == kDefaultOpticalDepth);
  CHECK(density("{optical_depth: 3.5}").density_relative);
  CHECK(density("{optical_depth: 3.5}").density_scale == 3.5);
  CHECK_FALSE(density("20").density_relative);
  CHECK(density("20").density_scale == 20.0);
  const std::string head = "renders: [{field: e, transfer_function: {density_scale: ";
  CHECK_THAT(config_error(head + "atuo}}]\n"),
             Contains("density_scale: atuo is not a density scale (allowed: a number >= 0") && Contains("auto"));
  CHECK_THAT(config_error(head + "{optical_depth: -1}}}]\n"), Contains("optical_depth: -1 is out of range (>= 0)"));
  CHECK_THAT(config_error(head + "{relative: 2}}}]\n"), Contains("relative: unknown key (allowed: optical_depth)"));
  CHECK_THAT(config_error(head + "-2}}]\n"), Contains("density_scale: -2 is out of range (>= 0)"));
}

TEST_CASE("renders without a name are named after their field, uniquely", "[config][defaults]") {
  const Config c = parse_config(R"yaml(renders:
  - {field: energy}
  - {field: energy, camera: {fov: 20}}
  - {name: energy_2, field: pressure}
  - {field: "rho/total (cgs)"}
  - {}
)yaml",
                                "n.yaml", "");
  REQUIRE(c.renders.size() == 5);
  CHECK(c.renders[0].name == "energy");
  CHECK(c.renders[1].name == "energy_3");  // energy_2 is the file's own
  CHECK(c.renders[2].name == "energy_2");
  CHECK(c.renders[3].name == "rho_total__cgs_");
  CHECK(c.renders[4].name == "render");
  CHECK(default_render_name(std::string(300, 'x')).size() == RenderSpec::kMaxName);
  // A name the file gives twice is still an error, at the second
  CHECK_THAT(config_error("renders: [{name: a}, {field: a}, {name: a}]\n"), Contains("duplicate render name \"a\""));
}

TEST_CASE("the effective config of the minimal one writes every default and reloads to it", "[config][defaults]") {
  const Config a = parse_config(kMinimal, "minimal.yaml", "");
  const std::string text = to_yaml(a);
  INFO(text);
  for (const char* key : {"name: \"energy\"", "position: {orbit: {azimuth: 35, elevation: 25, distance: fit}}",
                          "density_scale: {optical_depth: 16}", "opacity: [[0, 0], [0.5, 0.2], [1, 1]]",
                          "diffuse: \"viridis\"", "type: rect", "intensity: 60", "type: gradient", "width: 512"})
    CHECK(text.find(key) != std::string::npos);
  const Config b = parse_config(text, "effective.yaml", "");
  CHECK(to_yaml(b) == text);
  const RenderSpec& r = b.renders[0];
  CHECK(r.name == "energy");
  CHECK(r.transfer_function.density_relative);
  CHECK(r.transfer_function.density_scale == kDefaultOpticalDepth);
  CHECK(r.lights.size() == 1);
  CHECK(r.background.type == BackgroundType::Gradient);
  // The same scene from the minimal text and from its effective config
  const Bounds box{Vec3(0.0), Vec3(2.0, 3.0, 6.0)};
  const SceneDesc sa = build_scene(a.renders[0], box, {0.0, 1.0}, VolumeGeometry{box.lo, Vec3(0.5)});
  const SceneDesc sb = build_scene(r, box, {0.0, 1.0}, VolumeGeometry{box.lo, Vec3(0.5)});
  CHECK(sa.tf.density_scale == sb.tf.density_scale);
  CHECK(sa.camera.position == sb.camera.position);
  CHECK(sa.lights.size() == sb.lights.size());
}

TEST_CASE("the default extinction is relative to the data's diagonal", "[config][defaults]") {
  const RenderSpec r = parse_config(kMinimal, "minimal.yaml", "").renders[0];
  // density_scale times the diagonal is the optical depth, whatever the unit and the origin
  for (const double scale : {1e-6, 1.0, 1000.0, 3.7e5}) {
    const Bounds b{Vec3(-2.0, 5.0, 1.0) * scale, Vec3(1.0, 9.0, 13.0) * scale};  // diagonal 13
    const SceneDesc s = build_scene(r, b, {0.0, 1.0}, VolumeGeometry{b.lo, Vec3(0.5 * scale)});
    INFO("scale " << scale);
    CHECK(s.tf.density_scale * 13.0 * scale == Approx(kDefaultOpticalDepth).epsilon(1e-12));
    CHECK(resolve_density_scale(r.transfer_function, b) == s.tf.density_scale);
  }
  // A number is per world unit, as written
  TransferFunctionSpec fixed;
  fixed.density_scale = 7.0;
  CHECK(resolve_density_scale(fixed, Bounds{Vec3(0.0), Vec3(1e6)}) == 7.0);
  // Data without extent: nothing to be relative to, named
  CHECK_THROWS_WITH(resolve_density_scale(r.transfer_function, Bounds{Vec3(1.0), Vec3(1.0)}),
                    Contains("{optical_depth: 16} is relative to the data's diagonal") && Contains("diagonal of 0"));
}

TEST_CASE("the minimal config's picture is the same on data 1000 times larger", "[config][defaults]") {
  constexpr int n = 24;
  const std::vector<float> field = lumpy_field(n);
  const FieldView view = FieldView::contiguous(field.data(), DType::Float32, n, n, n);
  RenderSpec r = parse_config(kMinimal, "minimal.yaml", "").renders[0];
  r.image.width = 40;
  r.image.height = 32;
  r.image.spp = 4;
  const VolumeGeometry unit{Vec3(0.0), Vec3(1.0)};
  const VolumeGeometry big{Vec3(-5000.0, 300.0, 7.0), Vec3(1000.0)};  // metres -> millimetres, moved
  const Image a = render_image(r, view, unit);
  const Image b = render_image(r, view, big);
  CHECK(relative_difference(a, b) < 1e-4);

  // Not flat: the data shows against the background, bright and dark pixels both
  double sum = 0.0, sum2 = 0.0, lo = 1e30, hi = 0.0;
  const std::size_t pixels = std::size_t(a.width) * a.height;
  for (std::size_t i = 0; i < pixels; ++i) {
    const double y = luminance(a, i);
    sum += y;
    sum2 += y * y;
    lo = std::min(lo, y);
    hi = std::max(hi, y);
  }
  const double mean = sum / double(pixels);
  const double sd = std::sqrt(std::max(0.0, sum2 / double(pixels) - mean * mean));
  INFO("mean " << mean << " sd " << sd << " min " << lo << " max " << hi);
  CHECK(sd > 0.25 * mean);
  CHECK(hi > 4.0 * lo);

  // The same number per world unit on both would not do: the larger data is all but clear
  RenderSpec fixed = r;
  fixed.transfer_function.density_relative = false;
  fixed.transfer_function.density_scale = resolve_density_scale(r.transfer_function, field_bounds(view, unit));
  CHECK(relative_difference(render_image(fixed, view, unit), a) < 1e-12);
  CHECK(relative_difference(render_image(fixed, view, big), a) > 0.05);
}
