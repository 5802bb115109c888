// A complete config loads with every value where it belongs; defaults fill the rest.
#include "test_support.h"

#include <tessera/config/colormaps.h>

using namespace tessera;
using namespace tessera::config;
using tessera::config::test::TempDir;
using Catch::Matchers::Contains;

TEST_CASE("a full config loads with the values written", "[config]") {
  TempDir dir;
  dir.write("head.raw", "");
  const std::string path = dir.write("scene.yaml", test::full_config_yaml());
  const Config c = load_config(path);

  CHECK(c.path == path);
  CHECK(c.global.output_dir == "images");
  CHECK(c.global.on_error == OnError::Disable);
  CHECK(c.global.threads == 4);
  CHECK(c.global.render_final_step);
  CHECK(c.global.max_failures == 5);

  // Volume, file resolved against the YAML file's directory
  REQUIRE(c.volume);
  const VolumeSpec& v = *c.volume;
  CHECK(std::filesystem::equivalent(v.file, dir.file("head.raw")));
  CHECK(std::filesystem::path(v.file).is_absolute());
  CHECK(v.dims[0] == 4);
  CHECK(v.dims[1] == 3);
  CHECK(v.dims[2] == 2);
  CHECK(v.dtype == DType::UInt16);
  CHECK(v.spacing == Vec3(0.5, 0.25, 2.0));
  CHECK(v.origin == Vec3(1.0, 2.0, 3.0));
  CHECK(v.byte_order == ByteOrder::Big);
  CHECK(v.header_bytes == 16);

  REQUIRE(c.renders.size() == 3);
  const RenderSpec& r = c.renders[0];
  CHECK(r.name == "close");
  CHECK(r.field == "temperature");
  REQUIRE(r.trigger);
  CHECK(r.trigger->kind == TriggerSpec::Kind::Every);
  CHECK(r.trigger->every == 10);
  CHECK(r.image.width == 320);
  CHECK(r.image.height == 200);
  CHECK(r.image.spp == 8);
  CHECK(r.image.target_error == 0.01);
  CHECK(r.image.denoise);

  // Camera
  CHECK(r.camera.position.kind == PointSpec::Kind::Absolute);
  CHECK(r.camera.position.xyz == Vec3(2.0, 1.5, 2.5));
  CHECK(r.camera.look_at.xyz == Vec3(0.5, 0.5, 0.5));
  CHECK(r.camera.up == Vec3(0.0, 1.0, 0.0));
  CHECK(r.camera.fov == 45.0);
  CHECK(r.camera.aperture == 0.1);
  CHECK(r.camera.focus_distance == 3.0);

  // Transfer function
  const TransferFunctionSpec& tf = r.transfer_function;
  CHECK_FALSE(tf.range.automatic);
  CHECK(tf.range.lo == 280.0);
  CHECK(tf.range.hi == 400.0);
  CHECK(tf.density_scale == 20.0);
  REQUIRE(tf.opacity.size() == 3);
  CHECK(tf.opacity[1].u == 0.4);
  CHECK(tf.opacity[2].v == 1.0);
  REQUIRE(tf.diffuse.points.size() == 2);
  CHECK(tf.diffuse.colormap.empty());
  CHECK(tf.diffuse.points[1].c == Color(0.9, 0.2, 0.1));
  REQUIRE(tf.specular.points.size() == 1);
  CHECK(tf.specular.points[0].c == Color(0.04));
  REQUIRE(tf.roughness.size() == 2);
  CHECK(tf.roughness[1].v == 0.25);
  REQUIRE(tf.emission.points.size() == 2);
  CHECK(tf.emission.points[1].c == Color(2.0, 1.0, 0.5));

  // Lights, each of the kind its `type:` names (std::get throws for another)
  REQUIRE(r.lights.size() == 4);
  const auto& l0 = std::get<RectLightSpec>(r.lights[0]);
  CHECK(l0.position.xyz == Vec3(0.0, 0.0, 3.0));
  CHECK(l0.target.xyz == Vec3(0.5));
  CHECK_FALSE(l0.width.relative);
  CHECK(l0.width.value == 1.0);
  CHECK(l0.height.value == 2.0);
  CHECK(l0.intensity == 10.0);
  const auto& l1 = std::get<SphereLightSpec>(r.lights[1]);
  CHECK(l1.radius.value == 0.2);
  CHECK(l1.color == Color(1.0, 0.9, 0.8));
  const auto& l2 = std::get<RectLightSpec>(r.lights[2]);
  CHECK(l2.position.kind == PointSpec::Kind::Orbit);
  CHECK(l2.position.orbit.azimuth == 90.0);
  CHECK(l2.position.orbit.elevation == 45.0);
  CHECK(l2.position.orbit.distance == 3.0);
  CHECK(l2.target.kind == PointSpec::Kind::Center);  // default
  CHECK(l2.width.relative);
  CHECK(l2.height.value == 0.5);
  CHECK(l2.intensity == 1.0);  // default
  const auto& l3 = std::get<SphereLightSpec>(r.lights[3]);
  CHECK(l3.position.kind == PointSpec::Kind::Center);
  CHECK(l3.radius.relative);
  CHECK(l3.radius.value == 0.1);

  // Background
  CHECK(r.background.type == BackgroundType::Gradient);
  CHECK(r.background.top == Color(0.9, 0.9, 1.0));
  CHECK(r.background.bottom == Color(0.1));
  CHECK(r.background.up == Vec3(0.0, 1.0, 0.0));
  CHECK(r.background.intensity == 2.0);
  CHECK_FALSE(r.background.visible);

  // Integrator
  const IntegratorDesc& d = r.integrator.desc;
  CHECK(d.scattering == Scattering::Multiple);
  CHECK(d.max_bounces == 32);
  CHECK(d.rr_depth == 5);
  CHECK(d.shading == Shading::Brdf);
  CHECK(d.gradient_factor == 2.5);
  CHECK(d.phase_g == -0.3);
  CHECK(d.free_path == FreePath::Raymarch);
  CHECK(d.majorant == MajorantMode::Global);
  CHECK(d.macrocell == 8);
  CHECK(d.step == 0.25);
  CHECK(d.shadow == ShadowMode::Delta);
  CHECK_FALSE(d.shadow_roulette);
  CHECK(d.sampler == SamplerKind::Independent);
  CHECK(r.integrator.seed == 18446744073709551615ull);
  CHECK(r.integrator.tile == 0);
  CHECK(r.integrator.tile_order == TileOrder::Morton);

  // Output
  CHECK(r.output.file == "{name}/frame_{step:04d}_r{rank}");
  REQUIRE(r.output.formats.size() == 1);
  CHECK(r.output.formats[0] == ImageFormat::Png);
  CHECK(r.output.exposure == 1.5);
  CHECK(r.output.tonemap == ToneMap::Curve::Reinhard);
  CHECK(r.output.variance);
  CHECK(r.output.samples);
  REQUIRE(r.output.cinema);
  CHECK(r.output.cinema->azimuths == std::vector<double>{0.0, 90.0});
  CHECK(r.output.cinema->elevations == std::vector<double>{-30.0, 30.0});

  // Second render: orbit camera, auto range, colormap
  const RenderSpec& w = c.renders[1];
  CHECK(w.name == "wide-2");
  REQUIRE(w.trigger);
  CHECK(w.trigger->kind == TriggerSpec::Kind::At);
  CHECK(w.trigger->at == std::vector<std::int64_t>{0, 5, 100});
  CHECK(w.camera.position.kind == PointSpec::Kind::Orbit);
  CHECK(w.camera.position.orbit.azimuth == 30.0);
  CHECK(w.camera.look_at.kind == PointSpec::Kind::Center);
  CHECK(w.transfer_function.range.automatic);
  CHECK(w.transfer_function.diffuse.colormap == "viridis");

  const RenderSpec& h = c.renders[2];
  REQUIRE(h.trigger);
  CHECK(h.trigger->kind == TriggerSpec::Kind::When);
  CHECK(h.trigger->above == 350.0);
  CHECK(h.transfer_function.diffuse.colormap == "magma_r");
  CHECK(h.background.color == Color(0.2, 0.2, 0.25));

  CHECK(c.find_render("wide-2") == &c.renders[1]);
  CHECK(c.find_render("nope") == nullptr);
}

TEST_CASE("omitted keys take their documented defaults", "[config]") {
  const Config c = parse_config(R"(
renders:
  - name: a
    camera: {position: [0, 0, 5]}
    transfer_function: {opacity: [[0, 1]]}
)",
                                "mem.yaml", "");
  CHECK(c.path == "mem.yaml");
  CHECK(c.global.output_dir == "out");
  CHECK(c.global.on_error == OnError::Warn);
  CHECK(c.global.threads == 0);
  CHECK_FALSE(c.global.render_final_step);
  CHECK(c.global.max_failures == 3);
  CHECK_FALSE(c.volume);
  REQUIRE(c.renders.size() == 1);
  const RenderSpec& r = c.renders[0];
  CHECK(r.field.empty());
  CHECK_FALSE(r.trigger);
  CHECK(r.image.width == 512);
  CHECK(r.image.height == 512);
  CHECK(r.image.spp == 16);
  CHECK(r.image.target_error == 0.0);
  CHECK_FALSE(r.image.denoise);
  CHECK(r.camera.look_at.kind == PointSpec::Kind::Center);
  CHECK(r.camera.up == Vec3(0.0, 0.0, 1.0));
  CHECK(r.camera.fov == 30.0);
  CHECK(r.camera.aperture == 0.0);
  CHECK(r.camera.focus_distance == 0.0);
  CHECK(r.transfer_function.range.automatic);
  CHECK(r.transfer_function.density_scale == 1.0);
  CHECK_FALSE(r.transfer_function.diffuse.present());
  CHECK_FALSE(r.transfer_function.specular.present());
  CHECK(r.transfer_function.roughness.empty());
  CHECK(r.lights.empty());
  CHECK(r.background.type == BackgroundType::Constant);
  CHECK(r.background.color == Color(0.0));
  CHECK(r.background.intensity == 1.0);
  CHECK(r.background.visible);
  const IntegratorDesc core_defaults;
  CHECK(r.integrator.desc.scattering == core_defaults.scattering);
  CHECK(r.integrator.desc.max_bounces == core_defaults.max_bounces);
  CHECK(r.integrator.desc.shading == core_defaults.shading);
  CHECK(r.integrator.desc.step == core_defaults.step);
  CHECK(r.integrator.desc.macrocell == core_defaults.macrocell);
  CHECK(r.integrator.seed == 0);
  CHECK(r.integrator.tile == 8);
  CHECK(r.integrator.tile_order == TileOrder::RowMajor);
  CHECK(r.output.file == "{name}_{step:06d}");
  CHECK(r.output.formats == std::vector<ImageFormat>{ImageFormat::Exr, ImageFormat::Png});
  CHECK(r.output.exposure == 0.0);
  CHECK(r.output.tonemap == ToneMap::Curve::Aces);
  CHECK_FALSE(r.output.variance);
  CHECK_FALSE(r.output.samples);
  CHECK_FALSE(r.output.cinema);
}

TEST_CASE("an envmap background resolves its file against the YAML directory", "[config]") {
  TempDir dir;
  std::filesystem::create_directories(dir.path() / "maps");
  dir.write("maps/sky.exr", "not really an exr");
  const std::string path = dir.write("s.yaml", R"(renders:
  - name: a
    camera: {position: [0, 0, 5]}
    transfer_function: {opacity: [[0, 1]]}
    background: {type: envmap, file: maps/sky.exr, intensity: 0.5}
)");
  const Config c = load_config(path);
  const BackgroundSpec& b = c.renders[0].background;
  CHECK(b.type == BackgroundType::EnvMap);
  CHECK(std::filesystem::equivalent(b.file, dir.file("maps/sky.exr")));
  CHECK(b.intensity == 0.5);
}

TEST_CASE("a file that cannot be opened is a ConfigError naming it", "[config]") {
  try {
    load_config("/nonexistent/dir/scene.yaml");
    FAIL("no error");
  } catch (const ConfigError& e) {
    CHECK_THAT(e.what(), Contains("/nonexistent/dir/scene.yaml"));
    CHECK_THAT(e.what(), Contains("cannot open"));
  }
}

TEST_CASE("colormaps cover [0, 1] with colours in [0, 1]", "[config]") {
  for (const char* name : {"viridis", "magma", "inferno", "plasma", "coolwarm", "grayscale", "hot"}) {
    INFO(name);
    const auto pts = colormap(name);
    REQUIRE(pts.size() >= 16);
    CHECK(pts.front().u == 0.0);
    CHECK(pts.back().u == 1.0);
    for (const auto& p : pts) {
      CHECK(p.c.x >= 0.0);
      CHECK(p.c.x <= 1.0);
      CHECK(p.c.y >= 0.0);
      CHECK(p.c.z <= 1.0);
    }
  }
  // Reversed maps, greyscale ends
  CHECK(colormap("viridis_r").front().c == colormap("viridis").back().c);
  CHECK(colormap("grayscale").front().c == Color(0.0));
  CHECK(colormap("grayscale").back().c == Color(1.0));
  CHECK_THROWS_WITH(colormap("jet"), Contains("viridis"));
}

TEST_CASE("image.denoise must be a boolean", "[config]") {
  const std::string e = test::config_error("renders:\n  - name: a\n    camera: {position: [0, 0, 5]}\n"
                                           "    transfer_function: {opacity: [[0, 1]]}\n"
                                           "    image: {denoise: 3}\n");
  CHECK_THAT(e, Contains("scene.yaml:5:13: renders[0].image.denoise: 3 is not a boolean") &&
                    Contains("(allowed: true or false)"));
}

TEST_CASE("volume.association: vertex by default, cell on request, the far corner of the cells checked", "[config]") {
  TempDir dir;
  dir.write("v.raw", "");
  const std::string renders = "renders:\n  - name: a\n    camera: {position: [0, 0, 5]}\n"
                              "    transfer_function: {opacity: [[0, 1]]}\n";
  const auto load = [&](const std::string& volume) {
    return load_config(
        dir.write("scene.yaml", "volume: {file: v.raw, dims: [4, 3, 2], dtype: uint8" + volume + "}\n" + renders));
  };
  CHECK(load("").volume->association == Association::Vertex);
  const Config c = load(", association: cell");
  CHECK(c.volume->association == Association::Cell);
  CHECK(c.volume->geometry().association == Association::Cell);
  CHECK(load_config(dir.write("again.yaml", to_yaml(c))).volume->association == Association::Cell);
  CHECK_THROWS_WITH(load(", association: face"),
                    Contains("volume.association") && Contains("vertex") && Contains("cell"));
  // dims 4 along x: vertices reach origin + 3, cells origin + 4 spacings; 2^40 spacings of 1
  // from 0 is 1099511627776
  CHECK_NOTHROW(load(", origin: [1099511627772, 0, 0]"));
  CHECK_NOTHROW(load(", origin: [1099511627772, 0, 0], association: vertex"));
  CHECK_THROWS_WITH(load(", origin: [1099511627773, 0, 0], association: cell"),
                    Contains("beyond 2^40 smallest spacings"));
}
