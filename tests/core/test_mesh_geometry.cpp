// Mesh reconstruction and majorants (docs/physics.md section 10):
// - a field linear in x, y, z is reproduced exactly (to rounding) at random points of tets and
//   of parallelepiped hexes, unstructured and curvilinear;
// - Newton's inverse of the trilinear map converges on warped hexes to 1e-10, or check_mesh
//   reports the element;
// - over random meshes the macrocell majorant is never below the extinction at random points
//   of the elements that meet the cell, nor anywhere in the box;
// - outside every element the medium is empty.
// Seeds are fixed, so every outcome is reproducible.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "kernel/kernel_dispatch.h"
#include "mesh/mesh_tables.h"
#include "scene/prepared_scene_impl.h"
#include "test_mesh_support.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

using tessera::Vec3;
using namespace tessera_mesh_test;

namespace {

double linear(const Vec3& p) { return 0.5 + 1.5 * p.x - 2.0 * p.y + 0.75 * p.z; }

/// A 3x3x3 grid of parallelepipeds: edges a, b, c (a right-handed frame, sheared).
ElementList sheared_grid() {
  const Vec3 a(0.3, 0.05, -0.02), b(0.1, 0.25, 0.04), c(-0.05, 0.08, 0.2);
  return grid_hexes(3, 3, 3, Vec3(0.0), Vec3(1.0), linear,
                    [&](const Vec3& p) { return Vec3(1.0, -2.0, 0.5) + p.x * a + p.y * b + p.z * c; });
}

/// A random point of element e (random parametric or barycentric coordinates).
Vec3 random_point(const ElementList& m, std::size_t e, tessera::Rng& rng) {
  const auto& el = m.element[e];
  if (m.shape == tessera::Shape::Tet) {
    double w[4], s = 0.0;
    for (double& x : w) s += (x = -std::log(1.0 - rng.uniform()));
    Vec3 p(0.0);
    for (int k = 0; k < 4; ++k) p += (w[k] / s) * m.vertex[static_cast<std::size_t>(el[k])];
    return p;
  }
  Vec3 c[8];
  for (int k = 0; k < 8; ++k) c[k] = m.vertex[static_cast<std::size_t>(el[k])];
  const double r[3] = {rng.uniform(), rng.uniform(), rng.uniform()};
  return tessera::hex_map(c, r);
}

/// The mesh's value at world point x through the kernels' view (false outside).
bool mesh_value(const tessera::MeshTables& t, const Vec3& x, double* v) {
  const tessera::MeshFieldView view = t.view();
  return view.value((x - view.origin) / view.spacing, 0.0, 1.0, v);
}

void check_linear_exact(const ElementList& m, const tessera::Mesh& mesh) {
  tessera::check_mesh(mesh);
  tessera::MeshTables t;
  t.build(mesh);
  tessera::Rng rng(7, 0, 0, 0);
  double worst = 0.0;
  for (std::size_t e = 0; e < m.element.size(); ++e)
    for (int i = 0; i < 20; ++i) {
      const Vec3 x = random_point(m, e, rng);
      double v = NAN;
      REQUIRE(mesh_value(t, x, &v));
      worst = std::max(worst, std::fabs(v - linear(x)));
    }
  INFO("largest error " << worst);
  CHECK(worst < 1e-12);
}

}  // namespace

TEST_CASE("mesh: a linear field is exact on tets and on parallelepiped hexes", "[mesh]") {
  const ElementList hexes = sheared_grid();
  SECTION("unstructured hexes") { check_linear_exact(hexes, one_domain(hexes).mesh); }
  SECTION("a curvilinear grid") { check_linear_exact(hexes, curvilinear(hexes, 3, 3, 3).mesh); }
  SECTION("tets") {
    const ElementList tets = hexes_to_tets(hexes);
    check_linear_exact(tets, one_domain(tets).mesh);
  }
}

TEST_CASE("mesh: Newton's inverse converges on warped hexes, or check_mesh reports the element", "[mesh]") {
  tessera::Rng rng(19, 0, 0, 0);
  int accepted = 0, reported = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const double amount = 0.05 + 1.15 * rng.uniform();  // up to 120% of the edge: some fold over
    ElementList m = grid_hexes(1, 1, 1, Vec3(0.0), Vec3(1.0), linear);
    for (Vec3& v : m.vertex) v += amount * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
    const OwnedMesh om = one_domain(m);
    try {
      tessera::check_mesh(om.mesh);
    } catch (const std::invalid_argument& e) {
      CHECK(std::string(e.what()).find("mesh domain 0: element 0: hex is ") == 0);
      ++reported;
      continue;
    }
    ++accepted;
    Vec3 c[8];
    for (int k = 0; k < 8; ++k) c[k] = m.vertex[static_cast<std::size_t>(m.element[0][k])];
    for (int i = 0; i < 50; ++i) {
      const double r0[3] = {rng.uniform(), rng.uniform(), rng.uniform()};
      double r[3];
      REQUIRE(tessera::hex_inverse(c, tessera::hex_map(c, r0), r));
      for (int a = 0; a < 3; ++a) CHECK(std::fabs(r[a] - r0[a]) < 1e-10);
    }
  }
  INFO(accepted << " accepted, " << reported << " reported");
  CHECK(accepted > 50);
  CHECK(reported > 0);
}

TEST_CASE("mesh: a hex's corner Jacobian is the general Jacobian's determinant at the corner, bit for bit", "[mesh]") {
  // hex_corner_jacobian takes the edge vectors at the corner; hex_jacobian sums all eight
  // vertices with weights that are 0 or 1 there: the same numbers in every bit
  tessera::Rng rng(23, 0, 0, 0);
  for (int trial = 0; trial < 500; ++trial) {
    Vec3 c[8];
    for (int v = 0; v < 8; ++v) {
      const Vec3 corner(tessera::kHexCornerR[v], tessera::kHexCornerS[v], tessera::kHexCornerT[v]);
      c[v] = 3.7 * corner + 1.3 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) +
             Vec3(1e3 * trial, -0.25, 7.0);
    }
    for (int v = 0; v < 8; ++v) {
      const double r[3] = {static_cast<double>(tessera::kHexCornerR[v]), static_cast<double>(tessera::kHexCornerS[v]),
                           static_cast<double>(tessera::kHexCornerT[v])};
      Vec3 J[3];
      tessera::hex_jacobian(c, r, J);
      const double general = tessera::det3(J[0], J[1], J[2]), corner = tessera::hex_corner_jacobian(c, v);
      INFO("trial " << trial << ", vertex " << v);
      REQUIRE(std::memcmp(&general, &corner, sizeof general) == 0);
      REQUIRE(tessera::hex_vertex_at(tessera::kHexCornerR[v], tessera::kHexCornerS[v], tessera::kHexCornerT[v]) == v);
    }
  }
}

TEST_CASE("mesh: macrocell majorants bound the extinction over random meshes", "[mesh]") {
  tessera::Rng rng(23, 0, 0, 0);
  for (int trial = 0; trial < 6; ++trial) {
    const double warp = 0.2 * rng.uniform();
    ElementList m = grid_hexes(5, 4, 6, Vec3(-1.0, 0.0, 2.0), Vec3(0.3, 0.5, 0.2), linear, [&](const Vec3& p) {
      return p + warp * Vec3(std::sin(3.0 * p.y), std::cos(2.0 * p.z), std::sin(p.x + p.y)) * 0.2;
    });
    for (double& v : m.value) v = rng.uniform() * 3.0 - 1.0;  // a rough field
    if (trial % 2) m = hexes_to_tets(m);
    if (trial == 4) {
      m.association = tessera::Association::Cell;
      m.value.resize(m.element.size());
      for (double& v : m.value) v = rng.uniform();
    }
    const OwnedMesh om = one_domain(m);
    tessera::SceneDesc s;
    s.tf.lo = -1.0;
    s.tf.hi = 2.0;
    s.tf.density_scale = 5.0;
    s.tf.opacity = tessera::ScalarTF({0.0, 0.3, 0.6, 1.0}, {0.0, 1.0, 0.1, 0.7});  // not monotone
    s.integrator.macrocell = 1 + trial % 3;
    s.image = {8, 8, 1, 0.0};
    const tessera::PreparedScene ps = tessera::prepare(om.mesh, s);
    const tessera::KernelScene& k = tessera::prepared_scene_impl(ps).kernel;
    const tessera::GridMedium<tessera::MeshValue> med = tessera::make_medium<tessera::MeshValue>(k);
    const auto check_at = [&](const Vec3& p, int* bad) {
      std::int64_t c[3];
      for (int a = 0; a < 3; ++a)
        c[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(p[a] / k.cell_edge)), 0, k.cells[a] - 1);
      const double maj = k.majorant[(c[2] * k.cells[1] + c[1]) * k.cells[0] + c[0]];
      if (med.sigma_t(p) > maj) ++*bad;
    };
    int bad = 0;
    const Vec3 origin = k.origin, inv = k.inv_spacing;
    for (std::size_t e = 0; e < m.element.size(); ++e)
      for (int i = 0; i < 30; ++i) check_at((random_point(m, e, rng) - origin) * inv, &bad);
    for (int i = 0; i < 20000; ++i) {
      Vec3 p;
      for (int a = 0; a < 3; ++a) p[a] = rng.uniform() * static_cast<double>(k.field.dims[a] - 1);
      check_at(p, &bad);
    }
    INFO("trial " << trial);
    CHECK(bad == 0);
  }
}

TEST_CASE("mesh: outside every element the medium is empty", "[mesh]") {
  // An L-shaped mesh: the box's missing corner holds no element
  ElementList m = grid_hexes(2, 2, 1, Vec3(0.0), Vec3(1.0), [](const Vec3&) { return 1.0; });
  m.element.pop_back();
  const OwnedMesh om = one_domain(m);
  tessera::SceneDesc s;
  s.tf.density_scale = 2.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {1.0, 1.0});
  s.image = {8, 8, 1, 0.0};
  const tessera::PreparedScene ps = tessera::prepare(om.mesh, s);
  const tessera::KernelScene& k = tessera::prepared_scene_impl(ps).kernel;
  const auto med = tessera::make_medium<tessera::MeshValue>(k);
  const auto p_of = [&](const Vec3& x) { return (x - k.origin) * k.inv_spacing; };
  CHECK(med.sigma_t(p_of(Vec3(1.5, 1.5, 0.5))) == 0.0);
  CHECK(std::isnan(med.value(p_of(Vec3(1.5, 1.5, 0.5)))));
  CHECK(med.sigma_t(p_of(Vec3(0.5, 1.5, 0.5))) > 0.0);
  CHECK(med.value(p_of(Vec3(0.5, 0.5, 0.5))) == 1.0);
}
