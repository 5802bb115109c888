// Every kind of bad config is a ConfigError whose message starts with FILE:LINE:COL and the
// key path, and says what is allowed. Lines and columns are 1-based; a mapping value is
// reported at its key, a list element at itself.
#include "test_support.h"

using namespace tessera::config;
using tessera::config::test::config_error;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

/// A valid render whose camera block is `camera_lines` (each already indented 6 spaces);
/// the camera block starts on line 3, its first key on line 4.
std::string with_camera(const std::string& camera_lines) {
  return "renders:\n"
         "  - name: a\n"
         "    camera:\n" +
         camera_lines + "    transfer_function: {opacity: [[0, 1]]}\n";
}

/// A render with a valid camera (lines 1-3); `rest` starts on line 4 indented 4 spaces.
std::string render_with(const std::string& rest) {
  return "renders:\n"
         "  - name: a\n"
         "    camera: {position: [0, 0, 5]}\n" +
         rest;
}

}  // namespace

TEST_CASE("unknown keys name the key and list the allowed ones", "[config][errors]") {
  const std::string e = config_error(with_camera("      position: [0, 0, 5]\n"
                                                 "      fvo: 30\n"));
  CHECK_THAT(e, StartsWith("scene.yaml:5:7: renders[0].camera.fvo: unknown key"));
  CHECK_THAT(e, Contains("position, look_at, up, fov, aperture, focus_distance"));

  CHECK_THAT(config_error("tesera:\n  threads: 2\n"),
             StartsWith("scene.yaml:1:1: tesera: unknown key (allowed: tessera, volume, renders)"));

  // In a flow mapping inside a list: column of the key itself
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    lights:\n"
                                      "      - {type: sphere, position: [1, 1, 1], size: 2}\n")),
             StartsWith("scene.yaml:6:45: renders[0].lights[0].size: unknown key (allowed: type, "
                        "position, radius, color, intensity)"));
}

TEST_CASE("wrong types say what was found and what is allowed", "[config][errors]") {
  CHECK_THAT(config_error(with_camera("      position: [0, 0, 5]\n"
                                      "      fov: wide\n")),
             StartsWith("scene.yaml:5:7: renders[0].camera.fov: wide is not a number (allowed: a "
                        "number in (0, 180))"));
  // A quoted number is a string
  CHECK_THAT(config_error(with_camera("      position: [0, 0, 5]\n"
                                      "      fov: \"30\"\n")),
             StartsWith("scene.yaml:5:7: renders[0].camera.fov: \"30\" is not allowed here"));
  // A list where a mapping belongs
  CHECK_THAT(config_error("renders:\n  - name: a\n    camera: [1, 2]\n"),
             StartsWith("scene.yaml:3:5: renders[0].camera: a list is not allowed here (allowed: "
                        "a mapping with keys position"));
  // Inside nested lists: the element's own position
  const char* tf = "    transfer_function: {opacity: [[0, 1], [0.5, x]]}\n";
  CHECK_THAT(config_error(render_with(tf)),
             StartsWith("scene.yaml:4:49: renders[0].transfer_function.opacity[1][1]: x is not a number"));
  // Integers, booleans, points
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    image: {width: 12.5}\n")),
             StartsWith("scene.yaml:5:13: renders[0].image.width: 12.5 is not an integer (allowed: "
                        "an integer in [1, 16384])"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    output: {variance: yes}\n")),
             StartsWith("scene.yaml:5:14: renders[0].output.variance: yes is not a boolean (allowed: "
                        "true or false)"));
  CHECK_THAT(config_error(with_camera("      position: middle\n")),
             StartsWith("scene.yaml:4:7: renders[0].camera.position: middle is not a point (allowed: "
                        "[x, y, z], center or {orbit:"));
  CHECK_THAT(config_error(with_camera("      position: [0, 0]\n")),
             StartsWith("scene.yaml:4:7: renders[0].camera.position: list has 2 elements (allowed: [x, y, z])"));
  // An empty value is reported at its key
  CHECK_THAT(config_error(with_camera("      position:\n")),
             StartsWith("scene.yaml:4:7: renders[0].camera.position: an empty value is not allowed"));
}

TEST_CASE("out-of-range values give the allowed range", "[config][errors]") {
  CHECK_THAT(config_error(with_camera("      position: [0, 0, 5]\n"
                                      "      fov: 270\n")),
             StartsWith("scene.yaml:5:7: renders[0].camera.fov: 270 is out of range (0, 180)"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    image: {width: 0}\n")),
             StartsWith("scene.yaml:5:13: renders[0].image.width: 0 is out of range [1, 16384]"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    integrator:\n"
                                      "      phase_g: 1\n")),
             StartsWith("scene.yaml:6:7: renders[0].integrator.phase_g: 1 is out of range (-1, 1)"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    integrator: {max_bounces: 0}\n")),
             StartsWith("scene.yaml:5:18: renders[0].integrator.max_bounces: 0 is out of range [1, 1000000]"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    integrator: {macrocell: 257}\n")),
             Contains("renders[0].integrator.macrocell: 257 is out of range [1, 256]"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    integrator: {seed: -1}\n")),
             Contains("renders[0].integrator.seed: -1 is not an unsigned 64-bit integer"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]], density_scale: -2}\n")),
             Contains("renders[0].transfer_function.density_scale: -2 is out of range (>= 0)"));
  CHECK_THAT(config_error("tessera: {threads: -1}\n"),
             StartsWith("scene.yaml:1:11: tessera.threads: -1 is out of range [0, 65536]"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    lights: [{type: sphere, position: [0, 0, 1], radius: 0}]\n")),
             Contains("renders[0].lights[0].radius: 0 is out of range (> 0)"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    trigger: {every: 0}\n")),
             Contains("renders[0].trigger.every: 0 is out of range (>= 1)"));
  // Non-finite numbers are never accepted
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]], density_scale: .inf}\n")),
             Contains("renders[0].transfer_function.density_scale: .inf is not a number"));
}

TEST_CASE("missing required keys are reported at the enclosing block", "[config][errors]") {
  // name, camera, camera.position, transfer_function and opacity have defaults
  // (render_defaults.h; test_render_defaults.cpp)
  CHECK(config_error(with_camera("      fov: 30\n")).empty());
  CHECK_THAT(config_error("tessera:\n  threads: 1\n"), StartsWith("scene.yaml:1:1: renders: missing required key"));
  CHECK(config_error("renders:\n  - camera: {position: [0, 0, 5]}\n"
                     "    transfer_function: {opacity: [[0, 1]]}\n")
            .empty());
  CHECK(config_error(render_with("    transfer_function: {density_scale: 2}\n")).empty());
  CHECK_THAT(config_error(render_with("    transfer_function: {density_scale: {}}\n")),
             StartsWith("scene.yaml:4:25: renders[0].transfer_function.density_scale.optical_depth: missing required "
                        "key (allowed: t >= 0, the optical depth of the data's diagonal at opacity 1)"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    lights:\n"
                                      "      - {position: [0, 0, 1]}\n")),
             StartsWith("scene.yaml:6:9: renders[0].lights[0].type: missing required key (allowed: "
                        "rect or sphere)"));
  CHECK_THAT(config_error("renders: []\n"), StartsWith("scene.yaml:1:1: renders: list has 0 elements"));
}

TEST_CASE("a bad colormap name lists the colormaps", "[config][errors]") {
  const std::string e = config_error(render_with("    transfer_function:\n"
                                                 "      opacity: [[0, 1]]\n"
                                                 "      diffuse: virdis\n"));
  CHECK_THAT(e, StartsWith("scene.yaml:6:7: renders[0].transfer_function.diffuse: virdis is not a "
                           "colormap (allowed: "));
  for (const char* name : {"viridis", "magma", "inferno", "plasma", "coolwarm", "grayscale", "hot"})
    CHECK_THAT(e, Contains(name));
}

TEST_CASE("a bad output pattern names the placeholder", "[config][errors]") {
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    output:\n"
                                      "      file: \"{name}_{stp}\"\n")),
             StartsWith("scene.yaml:6:7: renders[0].output.file: bad output pattern \"{name}_{stp}\": "
                        "unknown placeholder {stp} (allowed: {name} {step} {time} {rank})"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    output: {file: \"{step:.3f}\"}\n")),
             StartsWith("scene.yaml:5:14: renders[0].output.file: bad output pattern"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    output: {file: \"a_{name\"}\n")),
             Contains("unclosed '{'"));
}

TEST_CASE("YAML syntax errors carry the parser's position", "[config][errors]") {
  CHECK_THAT(config_error("renders:\n  - name: a\n    camera: {position: [0, 0, 5]]\n"),
             StartsWith("scene.yaml:3:33: invalid YAML: illegal flow end"));
  CHECK_THAT(config_error("renders:\n  - name: a\n    camera: x: y\n"),
             StartsWith("scene.yaml:3:14: invalid YAML: illegal map value"));
  CHECK_THAT(config_error(""), StartsWith("scene.yaml: empty config"));
}

TEST_CASE("semantic checks: order, uniqueness, exclusivity", "[config][errors]") {
  // u must not decrease
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0.5, 0], [0.25, 1]]}\n")),
             Contains("renders[0].transfer_function.opacity[1][0]: 0.25 is less than the previous u 0.5"));
  // range lo < hi
  CHECK_THAT(config_error(render_with("    transfer_function: {range: [5, 5], opacity: [[0, 1]]}\n")),
             Contains("renders[0].transfer_function.range: lo 5 is not below hi 5"));
  // at most 64 TF points
  std::string many = "[";
  for (int i = 0; i < 65; ++i) many += (i ? ", " : "") + std::string("[0.5, 1]");
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: " + many + "]}\n")),
             Contains("renders[0].transfer_function.opacity: list has 65 elements"));
  // Diffuse colours are albedos
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]], diffuse: [[0, [1.5, 0, 0]]]}\n")),
             Contains("renders[0].transfer_function.diffuse[0][1][0]: 1.5 is out of range [0, 1]"));
  // Names: unique, restricted alphabet
  const std::string two = "renders:\n"
                          "  - name: a\n"
                          "    camera: {position: [0, 0, 5]}\n"
                          "    transfer_function: {opacity: [[0, 1]]}\n"
                          "  - name: a\n"
                          "    camera: {position: [0, 0, 5]}\n"
                          "    transfer_function: {opacity: [[0, 1]]}\n";
  CHECK_THAT(config_error(two), StartsWith("scene.yaml:5:5: renders[1].name: duplicate render name \"a\" "
                                           "(first used at line 2"));
  CHECK_THAT(config_error("renders:\n  - name: a b\n"),
             StartsWith("scene.yaml:2:5: renders[0].name: a b is not a valid name"));
  // Triggers: exactly one kind
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    trigger: {every: 2, at: [1]}\n")),
             StartsWith("scene.yaml:5:5: renders[0].trigger: give exactly one of every, at, when"));
  // Duplicate keys
  CHECK_THAT(config_error(with_camera("      fov: 30\n"
                                      "      fov: 40\n")),
             StartsWith("scene.yaml:5:7: renders[0].camera.fov: duplicate key (first given at line 4)"));
  // Formats once each; choices list the words
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    output: {formats: [exr, exr]}\n")),
             Contains("renders[0].output.formats[1]: exr given twice"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    integrator: {shading: smooth}\n")),
             Contains("renders[0].integrator.shading: smooth is not allowed (allowed: phase, brdf or hybrid)"));
  CHECK_THAT(config_error(render_with("    transfer_function: {opacity: [[0, 1]]}\n"
                                      "    integrator: {sampler: halton}\n")),
             Contains("renders[0].integrator.sampler: halton is not allowed (allowed: independent or sobol)"));
  // A camera looking at itself, a zero up vector
  CHECK_THAT(config_error(with_camera("      position: center\n")),
             Contains("renders[0].camera.position: camera position equals look_at"));
  CHECK_THAT(config_error(with_camera("      position: [0, 0, 5]\n"
                                      "      up: [0, 0, 0]\n")),
             StartsWith("scene.yaml:5:7: renders[0].camera.up: [0, 0, 0] has no direction"));
}

TEST_CASE("volume block: required keys and existing file", "[config][errors]") {
  const std::string renders = "renders:\n"
                              "  - name: a\n"
                              "    camera: {position: [0, 0, 5]}\n"
                              "    transfer_function: {opacity: [[0, 1]]}\n";
  CHECK_THAT(
      config_error("volume:\n  file: missing.raw\n  dims: [2, 2, 2]\n  dtype: uint8\n" + renders, "/nonexistent-dir"),
      StartsWith("scene.yaml:2:3: volume.file: file not found: /nonexistent-dir/missing.raw"));
  CHECK_THAT(config_error("volume:\n  dims: [2, 2, 2]\n" + renders),
             StartsWith("scene.yaml:1:1: volume.file: missing required key"));

  test::TempDir dir;
  dir.write("v.raw", "");
  const std::string base = dir.path().string();
  CHECK_THAT(config_error("volume:\n  file: v.raw\n  dims: [2, 2]\n  dtype: uint8\n" + renders, base),
             StartsWith("scene.yaml:3:3: volume.dims: list has 2 elements (allowed: [nx, ny, nz])"));
  CHECK_THAT(config_error("volume:\n  file: v.raw\n  dims: [2, 2, 2]\n  dtype: int32\n" + renders, base),
             StartsWith("scene.yaml:4:3: volume.dtype: int32 is not allowed (allowed: uint8, int16, "
                        "uint16, float32 or float64)"));
  CHECK_THAT(config_error("volume:\n  file: v.raw\n  dims: [2, 2, 2]\n  dtype: uint8\n"
                          "  spacing: [1, 0, 1]\n" +
                              renders,
                          base),
             StartsWith("scene.yaml:5:16: volume.spacing[1]: 0 is out of range [1e-100, 1e+100]"));
  CHECK(config_error("volume:\n  file: v.raw\n  dims: [2, 2, 2]\n  dtype: uint8\n" + renders, base).empty());
}
