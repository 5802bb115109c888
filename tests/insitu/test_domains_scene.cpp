// What the scene takes from a mesh of cell data or with rectilinear axes, through the adapter
// (tessera_execute_domains): `distance: fit` and the scene warnings use the medium's box (the
// cells' whole box; the coordinates' extent on a rectilinear axis, whatever origin and spacing
// say), `range: auto` covers every element, the memory estimate counts the axis tables, and
// a tiny rectilinear interval is refused with the 2^40-smallest-spacings message.
#include "domain_cuts.h"
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/config/build_scene.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using tessera_test::Axes;
using tessera_test::CutBox;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

const Dims kG{12, 10, 8};

struct Outcome {
  tessera_status status;
  std::string error;
  std::optional<tessera::Image> image;
  std::vector<std::string> warnings;
};

/// One render "view" of `extra` (camera, transfer function lines) over the domains.
Outcome run(const TempDir& dir, const std::string& name, const std::string& extra, const tessera_mesh& mesh,
            std::span<const tessera_domain> domains, const std::string& global = "", int size = 24) {
  Adapter ad;
  const std::string renders =
      render_yaml("view", "{every: 1}", extra + "    integrator: {seed: 3}\n", "density", size, 2);
  REQUIRE(ad.open(dir.write(name + ".yaml", config_yaml(dir.file(name), renders, global))) == TESSERA_OK);
  ad.set_quiet(true);
  Outcome o;
  o.status = ad.execute_domains(1, 0.0, mesh, domains);
  o.error = ad.last_error();
  if (const tessera::Image* img = ad.last_image("view")) o.image = *img;
  if (!ad.last_results().empty()) o.warnings = ad.last_results()[0].warnings;
  return o;
}

bool same_image(const tessera::Image& a, const tessera::Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string exact(const tessera::Vec3& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "[%.17g, %.17g, %.17g]", v.x, v.y, v.z);
  return buf;
}

/// The camera `distance: fit` gives over `box`, as absolute YAML (position and look_at).
std::string camera_fit_over(const tessera::Bounds& box) {
  using tessera::config::PointSpec;
  const tessera::Vec3 up(0, 0, 1);
  const tessera::Vec3 p = tessera::config::resolve_point(PointSpec::on_orbit_fit(30.0, 25.0), box, up,
                                                         tessera::config::fit_distance(40.0, 24, 24));
  return "    camera: {position: " + exact(p) + ", look_at: " + exact(box.center()) + ", up: [0, 0, 1], fov: 40}\n";
}

const std::string kFitCamera =
    "    camera: {position: {orbit: {azimuth: 30, elevation: 25, distance: fit}}, look_at: center, up: [0, 0, 1], "
    "fov: 40}\n";

/// A mesh whose rectilinear axes span another box than its origin and spacing describe:
/// x over [-0.5, 0.9], z over [-0.3, 0.2] (the coordinates), origin 0 and spacing 1 (unused).
class OffsetMesh {
 public:
  explicit OffsetMesh(tessera_association assoc) : m_mesh(tessera_test::unit_mesh(kG, assoc)) {
    const std::int64_t extra = assoc == TESSERA_CELL ? 1 : 0;
    m_x = tessera_test::stretched_axis(kG[0] + extra, 0.6);
    m_z = tessera_test::stretched_axis(kG[2] + extra, -0.5);
    for (double& c : m_x) c = -0.5 + 1.4 * (c + 0.5);
    for (double& c : m_z) c = -0.3 + 0.5 * (c + 0.5);
    m_x.back() = 0.9;
    m_z.back() = 0.2;
    for (int a : {0, 2}) m_mesh.origin[a] = 0.0, m_mesh.spacing[a] = 1.0;
    m_mesh.coords[0] = m_x.data();
    m_mesh.coords[2] = m_z.data();
  }
  const tessera_mesh& mesh() const { return m_mesh; }
  /// The medium's box: the coordinates' extent on x and z, the uniform y's box
  static tessera::Bounds box() { return {tessera::Vec3(-0.5, -0.5, -0.3), tessera::Vec3(0.9, 0.5, 0.2)}; }
  /// The box that origin and spacing would describe (what must not be used)
  tessera::Bounds uniform_box() const {
    const double n0 = static_cast<double>(kG[0] - (m_mesh.association == TESSERA_CELL ? 0 : 1));
    const double n2 = static_cast<double>(kG[2] - (m_mesh.association == TESSERA_CELL ? 0 : 1));
    return {tessera::Vec3(0.0, -0.5, 0.0), tessera::Vec3(n0, 0.5, n2)};
  }

 private:
  tessera_mesh m_mesh;
  std::vector<double> m_x, m_z;
};

}  // namespace

TEST_CASE("domains: distance: fit frames the cells' whole box and a rectilinear axis' coordinate extent",
          "[insitu][domains][scene]") {
  TempDir dir;
  const HeldDomains seven(kG, tessera_test::seven_cuts(kG));
  const auto domains = seven.of_rank(0, 1);
  // Cell data on uniform axes: the cells' box [-0.5, 0.5]^3, not the centres' box (half a
  // cell in); vertex data over the same box frames the same
  const tessera::Vec3 half(0.5 / kG[0], 0.5 / kG[1], 0.5 / kG[2]);
  const tessera::Bounds cells{tessera::Vec3(-0.5), tessera::Vec3(0.5)}, centres{cells.lo + half, cells.hi - half};
  for (const tessera_association assoc : {TESSERA_CELL, TESSERA_VERTEX}) {
    INFO((assoc == TESSERA_CELL ? "cell" : "vertex") << " data on uniform axes");
    const tessera_mesh mesh = tessera_test::unit_mesh(kG, assoc);
    const std::string tag = std::to_string(assoc);
    const Outcome fit = run(dir, "fit" + tag, kFitCamera, mesh, domains);
    const Outcome box = run(dir, "box" + tag, camera_fit_over(cells), mesh, domains);
    REQUIRE(fit.status == TESSERA_OK);
    REQUIRE(box.status == TESSERA_OK);
    CHECK(same_image(*fit.image, *box.image));
    if (assoc == TESSERA_CELL) {
      const Outcome inner = run(dir, "inner", camera_fit_over(centres), mesh, domains);
      CHECK_FALSE(same_image(*fit.image, *inner.image));
    }
  }
  // Rectilinear x and z over another box than origin and spacing describe
  for (const tessera_association assoc : {TESSERA_VERTEX, TESSERA_CELL}) {
    INFO((assoc == TESSERA_CELL ? "cell" : "vertex") << " data, x and z rectilinear");
    const OffsetMesh m(assoc);
    const std::string tag = std::to_string(10 + assoc);  // not the uniform tests' names
    const Outcome fit = run(dir, "fit" + tag, kFitCamera, m.mesh(), domains);
    const Outcome box = run(dir, "box" + tag, camera_fit_over(m.box()), m.mesh(), domains);
    REQUIRE(fit.status == TESSERA_OK);
    REQUIRE(box.status == TESSERA_OK);
    CHECK(same_image(*fit.image, *box.image));
    const Outcome wrong = run(dir, "wrong" + tag, camera_fit_over(m.uniform_box()), m.mesh(), domains);
    REQUIRE(wrong.status == TESSERA_OK);
    CHECK_FALSE(same_image(*fit.image, *wrong.image));
  }
}

TEST_CASE("domains: range: auto covers every element of cell data and rectilinear meshes, the last layer included",
          "[insitu][domains][scene]") {
  TempDir dir;
  // The field's largest value sits in the last element along every axis (a corner cell)
  std::vector<float> whole(static_cast<std::size_t>(kG[0] * kG[1] * kG[2]));
  for (std::int64_t k = 0; k < kG[2]; ++k)
    for (std::int64_t j = 0; j < kG[1]; ++j)
      for (std::int64_t i = 0; i < kG[0]; ++i)
        whole[static_cast<std::size_t>(i + kG[0] * (j + kG[1] * k))] = tessera_test::global_value(kG, i, j, k);
  whole.back() = 400.0f;
  tessera_field f{};
  f.name = "density";
  f.data = whole.data();
  f.dtype = TESSERA_FLOAT32;
  for (int a = 0; a < 3; ++a) f.dims[a] = kG[a];
  f.byte_strides[0] = 4;
  f.byte_strides[1] = 4 * kG[0];
  f.byte_strides[2] = 4 * kG[0] * kG[1];
  tessera_domain d{};
  d.fields = &f;
  d.nfields = 1;
  const std::span<const tessera_domain> one(&d, 1);
  const float lo = *std::min_element(whole.begin(), whole.end());
  const std::string tf = "density_scale: 40, opacity: [[0, 0], [1, 1]], diffuse: viridis}\n";
  for (const tessera_association assoc : {TESSERA_CELL, TESSERA_VERTEX})
    for (const Axes axes : {Axes::Uniform, Axes::StretchedAll}) {
      if (assoc == TESSERA_VERTEX && axes == Axes::Uniform) continue;
      INFO((assoc == TESSERA_CELL ? "cell" : "vertex") << " data, " << tessera_test::axes_name(axes));
      const tessera_test::TestMesh mesh(kG, assoc, axes);
      const std::string tag = std::to_string(assoc) + std::to_string(static_cast<int>(axes));
      const Outcome automatic = run(dir, "auto" + tag, "    transfer_function: {range: auto, " + tf, mesh.mesh(), one);
      const Outcome fixed =
          run(dir, "fixed" + tag, "    transfer_function: {range: [" + exact(lo) + ", 400], " + tf, mesh.mesh(), one);
      const Outcome short_range =
          run(dir, "short" + tag, "    transfer_function: {range: [" + exact(lo) + ", 250], " + tf, mesh.mesh(), one);
      REQUIRE(automatic.status == TESSERA_OK);
      REQUIRE(fixed.status == TESSERA_OK);
      CHECK(same_image(*automatic.image, *fixed.image));
      CHECK_FALSE(same_image(*automatic.image, *short_range.image));
    }
}

TEST_CASE("domains: the scene warnings name the cells' box and the rectilinear extent", "[insitu][domains][scene]") {
  TempDir dir;
  const HeldDomains seven(kG, tessera_test::seven_cuts(kG));
  const auto domains = seven.of_rank(0, 1);
  const std::string away = "    camera: {position: [20, 0, 0], look_at: [30, 0, 0], up: [0, 0, 1], fov: 40}\n";
  const auto warned = [&](const Outcome& o, const std::string& words) {
    INFO(o.error);
    REQUIRE(o.status == TESSERA_OK);
    for (const std::string& w : o.warnings)
      if (w.find(words) != std::string::npos) return true;
    for (const std::string& w : o.warnings) UNSCOPED_INFO("warning: " << w);
    return false;
  };
  const tessera_mesh cells = tessera_test::unit_mesh(kG, TESSERA_CELL);
  CHECK(warned(run(dir, "cells", away, cells, domains),
               "the data's bounds ([-0.5, 0.5] x [-0.5, 0.5] x [-0.5, 0.5]) are behind the camera"));
  for (const tessera_association assoc : {TESSERA_VERTEX, TESSERA_CELL}) {
    const OffsetMesh m(assoc);
    CHECK(warned(run(dir, std::to_string(20 + assoc), away, m.mesh(), domains),
                 "the data's bounds ([-0.5, 0.9] x [-0.5, 0.5] x [-0.3, 0.2]) are behind the camera"));
  }
}

TEST_CASE("domains: the memory estimate of a rectilinear mesh counts its axis tables", "[insitu][domains][memory]") {
  TempDir dir;
  const HeldDomains one(kG, {CutBox{{0, 0, 0}, kG}});
  const auto domains = one.of_rank(0, 1);
  // A 1 MiB limit that a 512x512 film exceeds: the message lists the estimate's parts
  const std::string limit = "  memory_limit_mb: 1\n";
  const Outcome uniform = run(dir, "uni", "", tessera_test::unit_mesh(kG, TESSERA_CELL), domains, limit, 512);
  CHECK(uniform.status != TESSERA_OK);
  CHECK_THAT(uniform.error, Catch::Contains("memory_limit_mb = 1 MiB") && !Catch::Contains("axis tables"));
  const tessera_test::TestMesh stretched(kG, TESSERA_CELL, Axes::StretchedY);
  const Outcome rect = run(dir, "rect", "", stretched.mesh(), domains, limit, 512);
  CHECK(rect.status != TESSERA_OK);
  CHECK_THAT(rect.error, Catch::Contains("memory_limit_mb = 1 MiB") && Catch::Contains("axis tables"));
}

TEST_CASE("domains: a tiny rectilinear interval is refused with the 2^40-smallest-spacings message",
          "[insitu][domains][scene]") {
  TempDir dir;
  const HeldDomains one(kG, {CutBox{{0, 0, 0}, kG}});
  const auto domains = one.of_rank(0, 1);
  // y over [-0.5, 0.5] with one interval of 1e-12: 2^40 of them is 1.1, which holds the data
  // (within 0.5 of 0) but not the camera at 3 data radii
  std::vector<double> y = tessera_test::stretched_axis(kG[1] + 1, 0.0);
  y[4] = y[3] + 1e-12;
  tessera_mesh mesh = tessera_test::unit_mesh(kG, TESSERA_CELL);
  mesh.coords[1] = y.data();
  const Outcome o = run(dir, "tiny", "", mesh, domains);
  CHECK(o.status != TESSERA_OK);
  CHECK_THAT(o.error, Catch::Contains("camera.position [") &&
                          Catch::Contains("lies beyond 2^40 smallest spacings (1.09952)") &&
                          Catch::Contains("where a double no longer resolves a voxel"));
  CHECK_FALSE(o.image);
  // The same mesh with the camera and the light within 1.1 of 0 renders
  const Outcome near = run(dir, "near",
                           "    camera: {position: [0.9, -0.3, 0.4], look_at: center, up: [0, 0, 1]}\n"
                           "    lights: [{type: sphere, position: [0.8, 0.2, 0.6], radius: 0.1, intensity: 20}]\n",
                           mesh, domains);
  INFO(near.error);
  CHECK(near.status == TESSERA_OK);
}
