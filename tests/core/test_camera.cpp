// Tests for Camera: invalid descriptions throw naming the fault; pixel (px, py) maps to the
// right direction (py = 0 on top, vertical fov exact); thin-lens rays converge on the focal
// point of their pixel's pinhole ray.
#include <tessera/camera.h>

#include <catch2/catch.hpp>

#include "sampling/rng.h"

#include <cmath>
#include <limits>

using tessera::Camera;
using tessera::CameraDesc;
using tessera::Vec3;

namespace {
double angle_deg(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180.0 / tessera::kPi;
}
}  // namespace

TEST_CASE("camera rejects invalid descriptions with a clear message", "[camera]") {
  CameraDesc d;
  d.position = Vec3(0.0, 0.0, 5.0);
  d.look_at = Vec3(0.0);
  SECTION("up parallel to the view direction") {
    d.up = Vec3(0.0, 0.0, 1.0);
    CHECK_THROWS_WITH(Camera(d, 8, 8), Catch::Contains("up") && Catch::Contains("parallel"));
    d.up = Vec3(0.0, 0.0, -3.0);
    CHECK_THROWS_WITH(Camera(d, 8, 8), Catch::Contains("parallel"));
  }
  SECTION("up is zero") {
    d.up = Vec3(0.0);
    CHECK_THROWS_WITH(Camera(d, 8, 8), Catch::Contains("up") && Catch::Contains("zero"));
  }
  SECTION("fov 0 and 180 (and beyond) are outside (0, 180)") {
    for (const double fov : {0.0, 180.0, -10.0, 200.0}) {
      d.fov_deg = fov;
      CHECK_THROWS_WITH(Camera(d, 8, 8), Catch::Contains("fov") && Catch::Contains("(0, 180)"));
    }
    d.fov_deg = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH(Camera(d, 8, 8), Catch::Contains("fov"));
  }
  SECTION("position equals look_at") {
    d.look_at = d.position;
    CHECK_THROWS_WITH(Camera(d, 8, 8), Catch::Contains("position equals look_at"));
  }
  SECTION("negative aperture or focus distance, non-finite position, empty image") {
    CameraDesc a = d;
    a.aperture = -0.1;
    CHECK_THROWS_WITH(Camera(a, 8, 8), Catch::Contains("aperture"));
    CameraDesc f = d;
    f.focus_distance = -1.0;
    CHECK_THROWS_WITH(Camera(f, 8, 8), Catch::Contains("focus_distance"));
    CameraDesc p = d;
    p.position.x = std::numeric_limits<double>::infinity();
    CHECK_THROWS_WITH(Camera(p, 8, 8), Catch::Contains("finite"));
    CHECK_THROWS_WITH(Camera(d, 0, 8), Catch::Contains("image size"));
  }
  SECTION("almost-parallel up is still accepted") {
    d.up = Vec3(1e-3, 0.0, 1.0);
    CHECK_NOTHROW(Camera(d, 8, 8));
  }
}

TEST_CASE("pinhole rays: centre along the view, vertical fov exact, py = 0 on top", "[camera]") {
  CameraDesc d;
  d.position = Vec3(1.0, 2.0, 3.0);
  d.look_at = Vec3(1.0, 2.0, -7.0);  // looking along -z, up +y
  d.fov_deg = 50.0;
  const int w = 40, h = 20;
  const Camera cam(d, w, h);
  const Vec3 fwd(0.0, 0.0, -1.0);
  const tessera::Ray centre = cam.generate(w / 2.0, h / 2.0, 0.5, 0.5);
  CHECK(centre.o == d.position);
  CHECK(glm::length(centre.d - fwd) < 1e-12);
  // Top and bottom edge midpoints are fov/2 away from the axis, top toward +y.
  const tessera::Ray top = cam.generate(w / 2.0, 0.0, 0.5, 0.5);
  const tessera::Ray bottom = cam.generate(w / 2.0, h, 0.5, 0.5);
  CHECK(angle_deg(top.d, fwd) == Approx(25.0).epsilon(1e-12));
  CHECK(angle_deg(bottom.d, fwd) == Approx(25.0).epsilon(1e-12));
  CHECK(top.d.y > 0.0);
  CHECK(bottom.d.y < 0.0);
  // Horizontal extent follows the aspect ratio: tan(h/2) = aspect * tan(v/2); px = 0 is left,
  // i.e. toward -x for a camera looking along -z with up +y (right = forward x up = +x).
  const tessera::Ray left = cam.generate(0.0, h / 2.0, 0.5, 0.5);
  CHECK(std::atan(std::fabs(left.d.x / left.d.z)) ==
        Approx(std::atan(2.0 * std::tan(25.0 * tessera::kPi / 180.0))).epsilon(1e-12));
  CHECK(left.d.x < 0.0);
  // Every direction is unit length
  tessera::Rng rng(1, 0, 0, 0);
  for (int i = 0; i < 100; ++i) {
    const tessera::Ray r = cam.generate(rng.uniform() * w, rng.uniform() * h, rng.uniform(), rng.uniform());
    CHECK(glm::length(r.d) == Approx(1.0).epsilon(1e-14));
  }
}

TEST_CASE("thin lens: every lens ray passes through its pixel's focal point", "[camera]") {
  CameraDesc d;
  d.position = Vec3(0.3, -0.2, 4.0);
  d.look_at = Vec3(0.0, 0.1, 0.0);
  d.up = Vec3(0.1, 1.0, 0.0);
  d.fov_deg = 35.0;
  d.aperture = 0.25;
  const int w = 32, h = 24;
  tessera::Rng rng(2, 0, 0, 0);
  for (const double focus : {0.0, 2.5, 9.0}) {
    d.focus_distance = focus;
    const double f = focus > 0.0 ? focus : glm::length(d.look_at - d.position);
    CameraDesc pin = d;
    pin.aperture = 0.0;
    const Camera lens(d, w, h), pinhole(pin, w, h);
    const Vec3 fwd = glm::normalize(d.look_at - d.position);
    double worst_miss = 0.0, worst_lens = 0.0;
    bool off_axis_origins = false;
    for (int i = 0; i < 500; ++i) {
      const double px = rng.uniform() * w, py = rng.uniform() * h;
      const tessera::Ray p = pinhole.generate(px, py, 0.5, 0.5);
      const Vec3 focal = p.o + p.d * (f / glm::dot(p.d, fwd));  // on the plane at distance f
      const tessera::Ray r = lens.generate(px, py, rng.uniform(), rng.uniform());
      // Distance from the focal point to the lens ray's line
      const Vec3 v = focal - r.o;
      worst_miss = std::fmax(worst_miss, glm::length(v - glm::dot(v, r.d) * r.d));
      // The origin lies on the lens disk: in the plane through the position, within aperture
      const Vec3 off = r.o - d.position;
      worst_lens = std::fmax(worst_lens, std::fabs(glm::dot(off, fwd)));
      CHECK(glm::length(off) <= d.aperture * (1.0 + 1e-12));
      off_axis_origins = off_axis_origins || glm::length(off) > 0.5 * d.aperture;
      CHECK(glm::dot(r.d, fwd) > 0.0);
    }
    INFO("focus distance " << f);
    CHECK(worst_miss < 1e-12 * (1.0 + f));
    CHECK(worst_lens < 1e-12);
    CHECK(off_axis_origins);
  }
}
