// `distance: fit`: the camera distance at which the data's bounding sphere just fills the
// smaller field of view. Checked through the real camera: every corner of the data bounds
// projects inside the image, and the sphere touches the edges of the narrower field of view.
#include "test_support.h"

#include <tessera/camera.h>
#include <tessera/config/build_scene.h>
#include <tessera/image_io.h>
#include <tessera/number_text.h>
#include <tessera/render.h>

#include "temp_dir.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

using namespace tessera;
using namespace tessera::config;
using Catch::Matchers::Contains;
using tessera::config::test::config_error;

namespace {

std::string fit_scene(double az, double el, double fov, int w, int h, const Vec3& up, double aperture = 0.0) {
  return "renders:\n  - name: a\n    image: {width: " + std::to_string(w) + ", height: " + std::to_string(h) +
         ", spp: 1}\n    camera:\n      position: {orbit: {azimuth: " + format_number(az) +
         ", elevation: " + format_number(el) + ", distance: fit}}\n      up: [" + format_number(up.x) + ", " +
         format_number(up.y) + ", " + format_number(up.z) + "]\n      fov: " + format_number(fov) +
         "\n      aperture: " + format_number(aperture) + "\n    transfer_function: {opacity: [[0, 1]]}\n";
}

SceneDesc build(const std::string& yaml, const Bounds& b) {
  const Config c = parse_config(yaml, "fit.yaml", "");
  return build_scene(c.renders[0], b, {0.0, 1.0}, VolumeGeometry{b.lo, Vec3(1.0)});
}

double deg(double d) { return d * kPi / 180.0; }

}  // namespace

TEST_CASE("fit_distance is 1 / sin(half the smaller field of view)", "[config][fit]") {
  CHECK(fit_distance(90.0, 100, 100) == Approx(std::sqrt(2.0)).epsilon(1e-14));
  // 35 degrees, square: about 3.33 radii (the figure a first user had to find by hand)
  CHECK(fit_distance(35.0, 64, 64) == Approx(1.0 / std::sin(deg(17.5))).epsilon(1e-14));
  // Wide images: the vertical fov is the smaller one, so the width does not matter
  CHECK(fit_distance(35.0, 400, 100) == Approx(fit_distance(35.0, 64, 64)).epsilon(1e-14));
  // Tall 1:4: the horizontal half-angle is atan(tan(17.5 deg) / 4)
  CHECK(fit_distance(35.0, 100, 400) == Approx(1.0 / std::sin(std::atan(std::tan(deg(17.5)) / 4.0))).epsilon(1e-14));
  CHECK(fit_distance(35.0, 100, 400) > fit_distance(35.0, 64, 64));
  CHECK_THROWS(fit_distance(0.0, 10, 10));
  CHECK_THROWS(fit_distance(180.0, 10, 10));
  CHECK_THROWS(fit_distance(30.0, 0, 10));
}

TEST_CASE("distance: fit frames the data at odd angles, fovs and aspect ratios", "[config][fit]") {
  // A box off the origin, longer in z, so corners stick out differently at every angle
  const Bounds b{Vec3(-3.0, 1.0, 2.0), Vec3(5.0, 2.5, 10.0)};
  const Vec3 c = b.center();
  const double R = b.radius();
  const std::vector<double> fovs{1.0, 7.5, 35.0, 90.0, 150.0, 170.0};
  const std::vector<std::pair<int, int>> sizes{{400, 100}, {100, 400}, {64, 64}, {300, 200}, {7, 1000}};
  const std::vector<std::pair<double, double>> angles{{0.0, 0.0},     {37.0, -23.0}, {123.0, 89.5},
                                                      {-71.0, -89.9}, {250.0, 60.0}, {359.0, 1e-3}};
  const std::vector<Vec3> ups{Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(1, 2, -3)};
  std::mt19937_64 rng(13);
  std::normal_distribution<double> gauss;
  std::vector<Vec3> sphere_points(500);
  for (Vec3& p : sphere_points) p = glm::normalize(Vec3(gauss(rng), gauss(rng), gauss(rng)));

  int cases = 0;
  for (double fov : fovs)
    for (const auto& [w, h] : sizes)
      for (const auto& [az, el] : angles)
        for (const Vec3& up : ups) {
          INFO("fov " << fov << ", " << w << "x" << h << ", azimuth " << az << ", elevation " << el << ", up " << up.x
                      << " " << up.y << " " << up.z);
          const SceneDesc s = build(fit_scene(az, el, fov, w, h, up), b);
          REQUIRE(s.camera.look_at == c);
          const Camera cam(s.camera, w, h);
          // Slack for rounding only: 1e-9 of the image edge
          const double sx = 1e-9 * w, sy = 1e-9 * h;

          // Every corner of the data bounds is inside the image
          for (int i = 0; i < 8; ++i) {
            const Vec3 corner((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
            double px = -1.0, py = -1.0;
            REQUIRE(cam.project(corner, &px, &py));
            CHECK(px >= -sx);
            CHECK(px <= w + sx);
            CHECK(py >= -sy);
            CHECK(py <= h + sy);
          }
          // So is every point of the bounding sphere
          bool sphere_inside = true;
          for (const Vec3& d : sphere_points) {
            double px = -1.0, py = -1.0;
            sphere_inside = sphere_inside && cam.project(c + R * d, &px, &py) && px >= -sx && px <= w + sx &&
                            py >= -sy && py <= h + sy;
          }
          CHECK(sphere_inside);

          // Fills: the sphere touches both edges of the narrower field of view. The frustum
          // plane at half-angle a has outward normal n = side cos(a) - forward sin(a); the
          // sphere's point c + R n must project onto the image edge.
          const Vec3 fwd = glm::normalize(s.camera.look_at - s.camera.position);
          const Vec3 right = glm::normalize(glm::cross(fwd, glm::normalize(up)));
          const Vec3 cam_up = glm::cross(right, fwd);
          const double tan_v = std::tan(deg(0.5 * fov));
          const double tan_h = tan_v * w / h;
          double px = 0.0, py = 0.0;
          if (tan_v <= tan_h) {
            const double a = std::atan(tan_v);
            REQUIRE(cam.project(c + R * (cam_up * std::cos(a) - fwd * std::sin(a)), &px, &py));
            CHECK(std::abs(py) <= sy);
            CHECK(std::abs(px - 0.5 * w) <= sx);
            REQUIRE(cam.project(c + R * (-cam_up * std::cos(a) - fwd * std::sin(a)), &px, &py));
            CHECK(std::abs(py - h) <= sy);
          } else {
            const double a = std::atan(tan_h);
            REQUIRE(cam.project(c + R * (right * std::cos(a) - fwd * std::sin(a)), &px, &py));
            CHECK(std::abs(px - w) <= sx);
            CHECK(std::abs(py - 0.5 * h) <= sy);
            REQUIRE(cam.project(c + R * (-right * std::cos(a) - fwd * std::sin(a)), &px, &py));
            CHECK(std::abs(px) <= sx);
          }
          // and the camera is exactly as far as the tangency needs, within 1e-9 relative
          CHECK(std::abs(glm::length(s.camera.position - c) / R - fit_distance(fov, w, h)) <=
                1e-9 * fit_distance(fov, w, h));
          ++cases;
        }
  CHECK(cases == 6 * 5 * 6 * 3);
}

TEST_CASE("distance: fit ignores the aperture (a thin lens frames like a pinhole)", "[config][fit]") {
  const Bounds b{Vec3(0.0), Vec3(2.0, 1.0, 1.0)};
  const SceneDesc pin = build(fit_scene(30, 20, 40, 320, 200, Vec3(0, 0, 1)), b);
  const SceneDesc lens = build(fit_scene(30, 20, 40, 320, 200, Vec3(0, 0, 1), 0.3), b);
  CHECK(pin.camera.position == lens.camera.position);
  CHECK(lens.camera.aperture == 0.3);
}

TEST_CASE("distance: fit is parsed for camera.position only and round-trips as a word", "[config][fit]") {
  const Config a = parse_config(fit_scene(30, 20, 40, 320, 200, Vec3(0, 0, 1)), "s.yaml", "");
  CHECK(a.renders[0].camera.position.is_fit());
  const std::string text = to_yaml(a);
  INFO(text);
  CHECK_THAT(text, Contains("distance: fit"));
  const Config b = parse_config(text, "r.yaml", "");
  CHECK(b.renders[0].camera.position.is_fit());
  CHECK(b.renders[0].camera.position.orbit.azimuth == 30.0);
  CHECK(to_yaml(b) == text);

  // The other point forms still work beside it
  const char* other = R"(renders:
  - name: a
    camera: {position: {orbit: {azimuth: 10, elevation: -5, distance: 2.5}}, look_at: [0, 0, 1]}
    transfer_function: {opacity: [[0, 1]]}
    lights: [{type: sphere, position: center, radius: 1}, {type: sphere, position: [1, 2, 3], radius: 1}]
)";
  const Config o = parse_config(other, "o.yaml", "");
  CHECK_FALSE(o.renders[0].camera.position.is_fit());
  CHECK(o.renders[0].camera.position.orbit.distance == 2.5);

  // A light (or look_at) has no field of view to fill
  const std::string light_fit = config_error(R"(renders:
  - name: a
    camera: {position: [0, 0, 5]}
    transfer_function: {opacity: [[0, 1]]}
    lights: [{type: sphere, position: {orbit: {azimuth: 0, elevation: 0, distance: fit}}, radius: 1}]
)");
  CHECK_THAT(light_fit, Contains("scene.yaml:5:"));
  CHECK_THAT(light_fit, Contains("only camera.position"));
  const std::string look_fit = config_error(R"(renders:
  - name: a
    camera: {position: [0, 0, 5], look_at: {orbit: {azimuth: 0, elevation: 0, distance: fit}}}
    transfer_function: {opacity: [[0, 1]]}
)");
  CHECK_THAT(look_fit, Contains("only camera.position"));
  // A misspelt word lists fit among what is allowed
  const std::string typo = config_error(R"(renders:
  - name: a
    camera: {position: {orbit: {azimuth: 0, elevation: 0, distance: fitt}}}
    transfer_function: {opacity: [[0, 1]]}
)");
  CHECK_THAT(typo, Contains("fitt is not a distance"));
  CHECK_THAT(typo, Contains("or fit"));
  CHECK_THAT(config_error(R"(renders:
  - name: a
    camera: {position: {orbit: {azimuth: 0, elevation: 0, distance: -1}}}
    transfer_function: {opacity: [[0, 1]]}
)"),
             Contains("out of range"));
}

TEST_CASE("a volume framed with distance: fit renders whole, with an empty border", "[config][fit]") {
  // An opaque box: a constant field that fills its bounds, a wide and a tall image
  const int n = 5;
  const std::vector<float> field(n * n * n, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), DType::Float32, n, n, n);
  const VolumeGeometry geom{Vec3(-1.0, 2.0, 0.5), Vec3(0.5, 0.3, 0.35)};  // a 2 x 1.2 x 1.4 box
  const Bounds b = field_bounds(view, geom);
  for (const auto& [w, h, az, el, fov] : std::vector<std::tuple<int, int, double, double, double>>{
           {96, 32, 37.0, 23.0, 35.0}, {32, 96, -110.0, -52.0, 70.0}, {48, 48, 200.0, 84.0, 20.0}}) {
    INFO(w << "x" << h << ", azimuth " << az << ", elevation " << el << ", fov " << fov);
    const std::string yaml = "renders:\n  - name: a\n    image: {width: " + std::to_string(w) +
                             ", height: " + std::to_string(h) +
                             ", spp: 2}\n    camera: {position: {orbit: {azimuth: " + format_number(az) +
                             ", elevation: " + format_number(el) + ", distance: fit}}, fov: " + format_number(fov) +
                             "}\n    transfer_function: {range: [0, 2], density_scale: 1000, "
                             "opacity: [[0, 1], [1, 1]]}\n    background: {type: constant, color: [0, 0, 0]}\n";
    const Config c = parse_config(yaml, "fit.yaml", "");
    const SceneDesc s = build_scene(c.renders[0], b, {1.0, 1.0}, geom);
    // Precondition of this check (not of the feature): the box's corners project at least one
    // pixel inside the edges, so a pixel of the outermost ring cannot see the box
    const Camera cam(s.camera, w, h);
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
      double px = 0.0, py = 0.0;
      REQUIRE(cam.project(corner, &px, &py));
      REQUIRE(px >= 1.0);
      REQUIRE(px <= w - 1.0);
      REQUIRE(py >= 1.0);
      REQUIRE(py <= h - 1.0);
    }
    const PreparedScene ps = prepare(view, s);
    Film film(w, h);
    RenderStats stats;
    render(ps, film, stats);
    const auto alpha = [&](int x, int y) { return film.at(x, y).a / static_cast<double>(film.at(x, y).n); };
    CHECK(alpha(w / 2, h / 2) > 0.99);
    double border = 0.0;
    for (int x = 0; x < w; ++x) border += alpha(x, 0) + alpha(x, h - 1);
    for (int y = 0; y < h; ++y) border += alpha(0, y) + alpha(w - 1, y);
    CHECK(border == 0.0);
  }
}

#ifdef TESSERA_RENDER_EXE
TEST_CASE("tessera-render --width/--height re-frame a distance: fit camera", "[config][fit][cli]") {
  // A 2:1 render shown at 60 x 160: framed for the 2:1 shape it would cut the box at the sides
  tessera_test::TempDir dir;
  const int n = 5;
  const std::vector<float> field(n * n * n, 1.0f);
  std::ofstream(dir.file("box.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(field.data()), static_cast<std::streamsize>(field.size() * sizeof(float)));
  dir.write("scene.yaml",
            "volume: {file: box.raw, dims: [5, 5, 5], dtype: float32, spacing: [0.5, 0.3, 0.35]}\n"
            "renders:\n  - name: a\n    image: {width: 160, height: 80, spp: 1}\n"
            "    camera: {position: {orbit: {azimuth: 37, elevation: 23, distance: fit}}, fov: 35}\n"
            "    transfer_function: {range: [0, 2], density_scale: 1000, opacity: [[0, 1], [1, 1]]}\n"
            "    background: {type: constant, color: [0, 0, 0]}\n    output: {file: a, formats: [exr]}\n");
  const std::string cmd = "cd '" + dir.path().string() +
                          "' && '" TESSERA_RENDER_EXE "' scene.yaml --quiet --width 60 --height 160 -o tall.exr";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const Image img = read_exr(dir.file("tall.exr"));
  REQUIRE(img.width == 60);
  REQUIRE(img.height == 160);
  const auto alpha = [&](int x, int y) { return img.rgba[4 * (static_cast<std::size_t>(y) * img.width + x) + 3]; };
  CHECK(alpha(30, 80) > 0.99f);
  double border = 0.0;
  for (int x = 0; x < img.width; ++x) border += alpha(x, 0) + alpha(x, img.height - 1);
  for (int y = 0; y < img.height; ++y) border += alpha(0, y) + alpha(img.width - 1, y);
  CHECK(border == 0.0);
}
#endif
