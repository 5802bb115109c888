// Rendering meshes (docs/physics.md section 10):
// - an axis-aligned hex mesh built from a uniform grid's cells, with the grid's vertex values,
//   renders as that grid; a tet mesh of a linear field (6 tets per cell) renders as the grid
//   of that field. Block z-test: two independent renders (own seeds), 36 blocks of 4x4
//   pixels, each |z| < 4.2 (per-block two-sided false-alarm probability 2.7e-5, about 1e-3
//   for the 36 blocks together, Bonferroni); standard errors from the film's per-pixel sample
//   variance. Seeds are fixed, so outcomes are reproducible;
// - the image is bit-identical for the same mesh cut into 1, 2 or 3 domains in any order,
//   with int32 or int64 indices, for 1 or 2 threads, and for a curvilinear grid against the
//   same cells as unstructured hexes.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "test_mesh_support.h"
#include "test_support.h"

#include <cmath>
#include <vector>

using tessera::Color;
using tessera::Vec3;
using namespace tessera_mesh_test;

namespace {

constexpr int kCells = 8;
constexpr double kH = 0.125;

double blobby(const Vec3& p) {
  const Vec3 d = p - Vec3(0.55, 0.45, 0.5);
  return std::exp(-8.0 * glm::dot(d, d)) + 0.3 * std::sin(6.0 * p.x) * std::cos(5.0 * p.z);
}

double linear(const Vec3& p) { return 0.2 + 0.5 * p.x + 0.3 * p.y - 0.2 * p.z; }

/// A scattering scene over the unit box, lit by a sphere light and the background (a dark
/// albedo: the image shows the medium's transmittance more than its in-scattering).
tessera::SceneDesc scene(std::uint64_t seed, double lo, double hi) {
  tessera::SceneDesc s;
  s.geometry.origin = Vec3(0.0);
  s.geometry.spacing = Vec3(kH);
  s.tf.lo = lo;
  s.tf.hi = hi;
  s.tf.density_scale = 6.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.05, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.35, 0.3, 0.25));
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(1.0);
  s.lights.push_back(tessera::SphereLightDesc{Vec3(1.6, 1.8, -0.6), 0.3, Color(25.0)});
  s.camera.position = Vec3(0.5, 0.5, 0.5) + Vec3(0.6, 0.9, -2.6);
  s.camera.look_at = Vec3(0.5);
  s.camera.fov_deg = 32.0;
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 6;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.macrocell = 2;
  s.image = {24, 24, 128, 0.0};
  s.options.seed = seed;
  return s;
}

tessera::Film render(const tessera::PreparedScene& ps) { return tessera_test::render_film(ps); }

void check_same_medium(const tessera::Mesh& mesh, const std::vector<double>& grid_values, double lo, double hi) {
  const tessera::FieldView grid =
      tessera::FieldView::contiguous(grid_values.data(), tessera::DType::Float64, kCells + 1, kCells + 1, kCells + 1);
  const tessera::Film a = render(tessera::prepare(mesh, scene(101, lo, hi)));
  const tessera::Film b = render(tessera::prepare(grid, scene(202, lo, hi)));
  const auto ma = tessera_test::luminance_stats(a), mb = tessera_test::luminance_stats(b);
  const double z = max_block_z(a, b, 4);
  INFO("mesh " << ma.mean << " +- " << ma.se << ", grid " << mb.mean << " +- " << mb.se << ", largest block |z| " << z);
  CHECK(ma.se > 0.0);
  CHECK(std::fabs(ma.mean - mb.mean) / std::sqrt(ma.se * ma.se + mb.se * mb.se) < 4.0);
  CHECK(z < 4.2);
}

/// Pixel sums equal bit for bit.
bool same_bits(const tessera::Film& a, const tessera::Film& b) {
  for (std::size_t i = 0; i < a.pixels().size(); ++i) {
    const tessera::PixelSums &p = a.pixels()[i], &q = b.pixels()[i];
    if (p.r != q.r || p.g != q.g || p.b != q.b || p.a != q.a || p.lum != q.lum || p.lum2 != q.lum2 || p.n != q.n)
      return false;
  }
  return true;
}

}  // namespace

TEST_CASE("mesh: the hex mesh of a uniform grid's cells renders as the grid", "[mesh]") {
  const ElementList m = grid_hexes(kCells, kCells, kCells, Vec3(0.0), Vec3(kH), blobby);
  check_same_medium(one_domain(m).mesh, m.value, -0.3, 1.2);
}

TEST_CASE("mesh: a tet mesh of a linear field renders as the grid of that field", "[mesh]") {
  const ElementList hexes = grid_hexes(kCells, kCells, kCells, Vec3(0.0), Vec3(kH), linear);
  check_same_medium(one_domain(hexes_to_tets(hexes)).mesh, hexes.value, -0.05, 0.85);
}

TEST_CASE("mesh: the image does not depend on the cut into domains, their order, indices or threads", "[mesh]") {
  constexpr int n = 5;
  const ElementList hexes = grid_hexes(n, n, n, Vec3(0.0), Vec3(0.2), blobby, [](const Vec3& p) {
    return p + 0.03 * Vec3(std::sin(4.0 * p.y), std::sin(4.0 * p.z), std::sin(4.0 * p.x));
  });
  const ElementList tets = hexes_to_tets(hexes);
  tessera::SceneDesc s = scene(7, -0.3, 1.2);
  s.image = {16, 16, 8, 0.0};
  const auto image = [&](const tessera::Mesh& mesh, int threads) {
    s.options.threads = threads;
    return render(tessera::prepare(mesh, s));
  };
  SECTION("tets in 1, 2 and 3 domains") {
    const tessera::Film ref = image(one_domain(tets).mesh, 1);
    tessera::Rng rng(3, 0, 0, 0);
    for (const int parts : {1, 2, 3}) {
      std::vector<int> part(tets.element.size());
      for (int& p : part) p = static_cast<int>(rng.uniform() * parts);
      std::vector<int> order(static_cast<std::size_t>(parts));
      for (int d = 0; d < parts; ++d) order[static_cast<std::size_t>(d)] = parts - 1 - d;
      for (const int threads : {1, 2}) {
        const OwnedMesh om = cut(tets, part, order, /*reverse=*/threads == 2, /*wide=*/parts == 2);
        INFO(parts << " domains, " << threads << " threads");
        CHECK(same_bits(ref, image(om.mesh, threads)));
      }
    }
  }
  SECTION("a curvilinear grid and its cells as unstructured hexes") {
    const tessera::Film ref = image(curvilinear(hexes, n, n, n).mesh, 2);
    CHECK(same_bits(ref, image(one_domain(hexes).mesh, 1)));
    std::vector<int> part(hexes.element.size());
    for (std::size_t e = 0; e < part.size(); ++e) part[e] = static_cast<int>(e % 3);
    CHECK(same_bits(ref, image(cut(hexes, part, {2, 0, 1}, true).mesh, 2)));
  }
}
