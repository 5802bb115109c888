// to_yaml writes the effective config; parse_config reads it back to the same config.
#include "test_support.h"

using namespace tessera;
using namespace tessera::config;
using tessera::config::test::TempDir;

TEST_CASE("to_yaml round-trips a full config", "[config][to_yaml]") {
  TempDir dir;
  dir.write("head.raw", "");
  const Config a = load_config(dir.write("scene.yaml", test::full_config_yaml()));
  const std::string text = to_yaml(a);
  INFO(text);
  // Parsed from another directory: file names are absolute, so they resolve the same
  const Config b = parse_config(text, "roundtrip.yaml", "/");
  CHECK(to_yaml(b) == text);

  // Spot checks that the values, not just the text, survive
  REQUIRE(b.volume);
  CHECK(b.volume->file == a.volume->file);
  CHECK(b.volume->byte_order == ByteOrder::Big);
  CHECK(b.global.on_error == OnError::Disable);
  REQUIRE(b.renders.size() == 3);
  CHECK(b.renders[0].camera.aperture == 0.1);
  CHECK(b.renders[0].image.denoise);
  CHECK(b.renders[0].integrator.seed == 18446744073709551615ull);
  CHECK(b.renders[0].integrator.desc.phase_g == -0.3);
  CHECK(b.renders[0].transfer_function.opacity[1].u == 0.4);
  CHECK(b.renders[0].output.file == "{name}/frame_{step:04d}_r{rank}");
  CHECK(std::get<RectLightSpec>(b.renders[0].lights[2]).width.relative);
  CHECK(b.renders[1].camera.position.kind == PointSpec::Kind::Orbit);
  CHECK(b.renders[1].transfer_function.range.automatic);
  CHECK(b.renders[1].transfer_function.diffuse.colormap == "viridis");
  CHECK(b.renders[2].trigger->above == 350.0);
}

TEST_CASE("to_yaml writes every default", "[config][to_yaml]") {
  const Config a = parse_config(R"(renders:
  - name: "null"
    camera: {position: [0.1, 0.2, 0.30000000000000004]}
    transfer_function: {opacity: [[0, 1]]}
)",
                                "m.yaml", "");
  const std::string text = to_yaml(a);
  INFO(text);
  for (const char* key : {"output_dir:", "on_error: warn", "max_failures: 3", "width: 512", "fov: 30", "up: [0, 0, 1]",
                          "look_at: center", "range: auto", "scattering: single", "tile: 8", "tile_order: row",
                          "formats: [exr, png]", "tonemap: aces", "background:", "lights: []"})
    CHECK(text.find(key) != std::string::npos);
  const Config b = parse_config(text, "m2.yaml", "");
  CHECK(b.renders[0].name == "null");                                // quoted: stays a string
  CHECK(b.renders[0].camera.position.xyz.z == 0.30000000000000004);  // exact doubles
  CHECK(to_yaml(b) == text);
}
