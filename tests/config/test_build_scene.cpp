// From specs to core scenes: orbit and centre points, relative lengths, TF range, lights.
#include "light_lookup.h"
#include "test_support.h"

#include <tessera/config/build_scene.h>
#include <tessera/config/colormaps.h>

#include <cmath>
#include <limits>

using namespace tessera;
using namespace tessera::config;
using Catch::Matchers::Contains;

namespace {

constexpr double kEps = 1e-12;

bool near(const Vec3& a, const Vec3& b, double eps = kEps) { return glm::length(a - b) < eps; }

double deg(double d) { return d * kPi / 180.0; }

const char* kScene = R"(renders:
  - name: a
    image: {width: 64, height: 48, spp: 3}
    camera:
      position: {orbit: {azimuth: 90, elevation: 0, distance: 2}}
      fov: 40
      aperture: 0.5
    transfer_function:
      range: auto
      density_scale: 3
      opacity: [[0, 0], [1, 1]]
      diffuse: viridis
    lights:
      - {type: rect, position: {orbit: {azimuth: 0, elevation: 90, distance: 3}}, size: [{relative: 0.5}, 2], color: [1, 0.5, 0.25], intensity: 4}
      - {type: sphere, position: [9, 9, 9], radius: {relative: 0.25}, intensity: 2}
    background: {type: gradient, top: [1, 1, 1], up: [0, 1, 0], intensity: 3, visible: false}
    integrator: {seed: 77, tile: 16, tile_order: morton, scattering: multiple, phase_g: 0.5}
)";

}  // namespace

TEST_CASE("orbit directions about up = +z: reference +x, azimuth toward +y", "[config][orbit]") {
  const Vec3 z(0, 0, 1);
  CHECK(near(orbit_direction({0, 0, 1}, z), Vec3(1, 0, 0)));
  CHECK(near(orbit_direction({90, 0, 1}, z), Vec3(0, 1, 0)));
  CHECK(near(orbit_direction({180, 0, 1}, z), Vec3(-1, 0, 0)));
  CHECK(near(orbit_direction({0, 90, 1}, z), Vec3(0, 0, 1)));
  CHECK(near(orbit_direction({0, -90, 1}, z), Vec3(0, 0, -1)));
  CHECK(near(orbit_direction({30, 20, 1}, z),
             Vec3(std::cos(deg(20)) * std::cos(deg(30)), std::cos(deg(20)) * std::sin(deg(30)), std::sin(deg(20)))));
  // Length of up does not matter
  CHECK(near(orbit_direction({30, 20, 1}, Vec3(0, 0, 7)), orbit_direction({30, 20, 1}, z)));
}

TEST_CASE("orbit directions about other up vectors", "[config][orbit]") {
  // up = +y: x is the least aligned axis, e2 = up x e1 = -z
  const Vec3 y(0, 1, 0);
  CHECK(near(orbit_direction({0, 0, 1}, y), Vec3(1, 0, 0)));
  CHECK(near(orbit_direction({90, 0, 1}, y), Vec3(0, 0, -1)));
  CHECK(near(orbit_direction({0, 45, 1}, y), Vec3(std::sqrt(0.5), std::sqrt(0.5), 0)));
  // up = +x: y is the least aligned (first on a tie with z), e2 = x cross y = +z
  CHECK(near(orbit_direction({0, 0, 1}, Vec3(1, 0, 0)), Vec3(0, 1, 0)));
  CHECK(near(orbit_direction({90, 0, 1}, Vec3(1, 0, 0)), Vec3(0, 0, 1)));
  // Tilted up: the reference is z, already normal to up
  const Vec3 up = glm::normalize(Vec3(1, 1, 0));
  const Vec3 d0 = orbit_direction({0, 0, 1}, up);
  CHECK(near(d0, Vec3(0, 0, 1)));
  for (double az : {0.0, 45.0, 123.0, 300.0}) {
    const Vec3 d = orbit_direction({az, 0, 1}, up);
    CHECK(std::abs(glm::dot(d, up)) < kEps);  // elevation 0: in the plane normal to up
    CHECK(std::abs(glm::length(d) - 1.0) < kEps);
  }
  CHECK(std::abs(glm::dot(orbit_direction({77, 30, 1}, up), up) - std::sin(deg(30))) < kEps);
}

TEST_CASE("points resolve against the data bounds", "[config][orbit]") {
  const Bounds b{Vec3(0, 0, 0), Vec3(2, 4, 4)};  // centre (1, 2, 2), radius 3
  const Vec3 z(0, 0, 1);
  REQUIRE(b.radius() == 3.0);
  CHECK(resolve_point(PointSpec::center(), b, z) == Vec3(1, 2, 2));
  CHECK(resolve_point(PointSpec::absolute(Vec3(5, 6, 7)), b, z) == Vec3(5, 6, 7));
  CHECK(near(resolve_point(PointSpec::on_orbit(90, 0, 2), b, z), Vec3(1, 8, 2)));
  CHECK(near(resolve_point(PointSpec::on_orbit(0, 90, 1), b, z), Vec3(1, 2, 5)));
  CHECK(near(resolve_point(PointSpec::on_orbit(0, 0, 0), b, z), Vec3(1, 2, 2)));
  CHECK(LengthSpec::relative_to_radius(0.5).resolve(b.radius()) == 1.5);
  CHECK(LengthSpec::world(0.5).resolve(b.radius()) == 0.5);
}

TEST_CASE("transfer function range: fixed, auto, widened auto", "[config][scene]") {
  RangeSpec fixed{false, 280.0, 400.0};
  CHECK(resolve_range(fixed, {0.0, 1.0}) == std::pair(280.0, 400.0));
  RangeSpec automatic{true, 0.0, 1.0};
  CHECK(resolve_range(automatic, {-3.0, 7.0}) == std::pair(-3.0, 7.0));
  CHECK(resolve_range(automatic, {5.0, 5.0}) == std::pair(4.5, 5.5));
}

TEST_CASE("build_scene fills every part of the SceneDesc", "[config][scene]") {
  const Config c = parse_config(kScene, "s.yaml", "");
  const RenderSpec& r = c.renders[0];
  const Bounds b{Vec3(0, 0, 0), Vec3(2, 4, 4)};  // centre (1, 2, 2), radius 3
  const VolumeGeometry geom{Vec3(0.0), Vec3(0.5, 1.0, 1.0)};
  const SceneDesc s = build_scene(r, b, {10.0, 20.0}, geom);

  CHECK(s.geometry.spacing == Vec3(0.5, 1.0, 1.0));
  CHECK(s.image.width == 64);
  CHECK(s.image.height == 48);
  CHECK(s.image.spp == 3);

  // Camera on the orbit at azimuth 90 about +z, 2 radii out; looks at the centre
  CHECK(near(s.camera.position, Vec3(1, 8, 2)));
  CHECK(s.camera.look_at == Vec3(1, 2, 2));
  CHECK(s.camera.up == Vec3(0, 0, 1));
  CHECK(s.camera.fov_deg == 40.0);
  CHECK(s.camera.aperture == 0.5);

  // TF: auto range, colormap expanded
  CHECK(s.tf.lo == 10.0);
  CHECK(s.tf.hi == 20.0);
  CHECK(s.tf.density_scale == 3.0);
  CHECK(s.tf.opacity.eval(0.5) == Approx(0.5));
  const auto viridis = colormap("viridis");
  CHECK(s.tf.diffuse.size() == static_cast<int>(viridis.size()));
  CHECK(near(s.tf.diffuse.eval(1.0), viridis.back().c));
  CHECK(s.tf.specular.is_zero());
  CHECK(s.tf.emission.is_zero());
  CHECK(s.tf.roughness.eval(0.3) == 0.5);  // core default

  // Lights: radiance = color * intensity, relative sizes in radii
  REQUIRE(tessera::count_lights<tessera::RectLightDesc>(s.lights) == 1);
  const RectLightDesc& rect = tessera::nth_light<tessera::RectLightDesc>(s.lights, 0);
  CHECK(near(rect.position, Vec3(1, 2, 11)));
  CHECK(rect.target == Vec3(1, 2, 2));
  CHECK(rect.width == 1.5);
  CHECK(rect.height == 2.0);
  CHECK(rect.radiance == Color(4.0, 2.0, 1.0));
  REQUIRE(tessera::count_lights<tessera::SphereLightDesc>(s.lights) == 1);
  CHECK(tessera::nth_light<tessera::SphereLightDesc>(s.lights, 0).center == Vec3(9, 9, 9));
  CHECK(tessera::nth_light<tessera::SphereLightDesc>(s.lights, 0).radius == 0.75);
  CHECK(tessera::nth_light<tessera::SphereLightDesc>(s.lights, 0).radiance == Color(2.0));

  // Background, integrator, options
  CHECK(s.background.type == BackgroundType::Gradient);
  CHECK(s.background.up == Vec3(0, 1, 0));
  CHECK(s.background.intensity == 3.0);
  CHECK_FALSE(s.background.visible);
  CHECK(s.background.envmap == nullptr);
  CHECK(s.integrator.scattering == Scattering::Multiple);
  CHECK(s.integrator.phase_g == 0.5);
  CHECK(s.options.seed == 77);
  CHECK(s.options.tile == 16);
  CHECK(s.options.order == TileOrder::Morton);
  CHECK(s.options.threads == 0);

  GlobalOptions g;
  g.threads = 6;
  const RenderOptions o = build_render_options(r, g);
  CHECK(o.threads == 6);
  CHECK(o.seed == 77);
  CHECK(o.frame == 0);
}

TEST_CASE("an envmap background needs its image", "[config][scene]") {
  test::TempDir dir;
  dir.write("sky.exr", "x");
  const Config c = parse_config(R"(renders:
  - name: a
    camera: {position: [0, 0, 5]}
    transfer_function: {opacity: [[0, 1]]}
    background: {type: envmap, file: sky.exr}
)",
                                "s.yaml", dir.path().string());
  const Bounds b{Vec3(0.0), Vec3(1.0)};
  const VolumeGeometry g;
  CHECK_THROWS_WITH(build_scene(c.renders[0], b, {0, 1}, g, nullptr), Contains("not loaded"));
  auto img = std::make_shared<Image>();
  img->width = img->height = 1;
  img->rgba = {1, 1, 1, 1};
  const SceneDesc s = build_scene(c.renders[0], b, {0, 1}, g, img);
  CHECK(s.background.type == BackgroundType::EnvMap);
  CHECK(s.background.envmap.get() == img.get());
  // Reading a file that is no EXR fails naming it
  CHECK_THROWS_WITH(build_scene(c.renders[0], b, {0, 1}, g), Contains("sky.exr"));
}

TEST_CASE("range: auto of a constant field stays non-empty for huge values", "[config][scene]") {
  // Found by fuzz/fuzz_raw_volume: a field whose only finite value was 5.5e306 widened to
  // [v - 0.5, v + 0.5] == [v, v] in rounding, which prepare() refuses.
  RangeSpec automatic;
  automatic.automatic = true;
  for (const double v :
       {5.5e306, -5.5e306, 1e12, std::numeric_limits<double>::max(), -std::numeric_limits<double>::max()}) {
    const auto [lo, hi] = resolve_range(automatic, {v, v});
    INFO("value " << v << ": [" << lo << ", " << hi << "]");
    CHECK(std::isfinite(lo));
    CHECK(std::isfinite(hi));
    CHECK(lo < hi);
    CHECK(lo <= v);
    CHECK(v <= hi);
  }
  CHECK(resolve_range(automatic, {5.0, 5.0}) == std::pair(4.5, 5.5));  // unchanged where 0.5 shows
}

TEST_CASE("the early 2^40-smallest-spacings check reads the spacing of uniform axes only", "[config][scene]") {
  // A rectilinear axis' spacing is not its intervals (prepare() checks its smallest interval
  // exactly): a tiny value there refuses nothing; on a uniform axis it still does
  const Config c = parse_config(R"(renders:
  - name: a
    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: 3}}}
    transfer_function: {opacity: [[0, 1]]}
)",
                                "s.yaml", "");
  const Bounds b{Vec3(-0.5), Vec3(0.5)};
  const double coords[3] = {-0.5, 0.1, 0.5};  // never read here
  VolumeGeometry g;
  g.spacing = Vec3(0.5, 1e-20, 0.5);
  CHECK_THROWS_WITH(build_scene(c.renders[0], b, {0, 1}, g, nullptr),
                    Contains("camera.position [") && Contains("lies beyond 2^40 smallest spacings"));
  g.coords[1] = coords;
  const SceneDesc s = build_scene(c.renders[0], b, {0, 1}, g, nullptr);
  CHECK(glm::length(s.camera.position) > 1.0);
  // Every axis rectilinear: no early check at all; one uniform axis: its spacing counts
  g.spacing = Vec3(1e-20);
  g.coords[0] = g.coords[2] = coords;
  CHECK_NOTHROW(build_scene(c.renders[0], b, {0, 1}, g, nullptr));
  g.coords[2] = nullptr;
  CHECK_THROWS_WITH(build_scene(c.renders[0], b, {0, 1}, g, nullptr), Contains("lies beyond 2^40 smallest spacings"));
}
