// Tests for GridMedium: trilinear reconstruction is exact on linear fields (faces and edges
// included), degenerate axes (1 or 2 vertices) work, non-finite vertices map into the TF
// range, gradients are exact on linear fields, and the macrocell DDA visits the right cells.
#include <catch2/catch.hpp>

#include "kernel/grid_medium.h"
#include "sampling/rng.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using tessera::FieldView;
using tessera::Vec3;
using tessera_test::make_medium;

namespace {

struct Linear {
  double a, b, c, d;
  double operator()(const Vec3& p) const { return a + b * p.x + c * p.y + d * p.z; }
};

std::vector<double> sample_linear(const Linear& f, std::int64_t nx, std::int64_t ny, std::int64_t nz) {
  std::vector<double> v(static_cast<std::size_t>(nx * ny * nz));
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        v[(k * ny + j) * nx + i] = f(Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)));
  return v;
}

/// Random points inside the box [0, n-1]^3, a third of the coordinates snapped to a face
/// (0 or n-1) or to a vertex plane, so faces, edges and corners are all visited.
Vec3 random_point(tessera::Rng& rng, const std::int64_t n[3]) {
  Vec3 p;
  for (int a = 0; a < 3; ++a) {
    const double hi = static_cast<double>(n[a] - 1);
    const double r = rng.uniform();
    if (r < 0.12) p[a] = 0.0;
    else if (r < 0.24) p[a] = hi;
    else if (r < 0.33) p[a] = std::floor(rng.uniform() * (hi + 1.0));
    else p[a] = hi * rng.uniform();
  }
  return p;
}

}  // namespace

TEST_CASE("trilinear interpolation reproduces linear fields exactly", "[grid_medium]") {
  tessera::Rng rng(7, 0, 0, 0);
  tessera::TransferFunction tf;
  const std::int64_t shapes[][3] = {{5, 7, 4}, {2, 3, 9}, {1, 6, 5}, {8, 1, 2},
                                    {2, 2, 2}, {1, 1, 7}, {1, 1, 1}, {17, 2, 1}};
  for (const auto& shape : shapes) {
    const Linear f{rng.uniform() * 10 - 5, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2};
    const std::vector<double> data = sample_linear(f, shape[0], shape[1], shape[2]);
    const FieldView view = FieldView::contiguous(data.data(), tessera::DType::Float64, shape[0], shape[1], shape[2]);
    const auto m = make_medium<double>(view, tf);
    double worst = 0.0;
    for (int s = 0; s < 3000; ++s) {
      Vec3 p = random_point(rng, shape);
      // Along an axis with one vertex the field is constant there: compare at coordinate 0.
      Vec3 q = p;
      for (int a = 0; a < 3; ++a)
        if (shape[a] == 1) q[a] = 0.0;
      worst = std::fmax(worst, std::fabs(m.value(p) - f(q)));
    }
    INFO("shape " << shape[0] << "x" << shape[1] << "x" << shape[2]);
    CHECK(worst < 1e-12);
  }
}

TEST_CASE("points outside the box take the value at the clamped point", "[grid_medium]") {
  const Linear f{1.0, 0.5, -0.25, 2.0};
  const std::vector<double> data = sample_linear(f, 4, 3, 5);
  const FieldView view = FieldView::contiguous(data.data(), tessera::DType::Float64, 4, 3, 5);
  tessera::TransferFunction tf;
  const auto m = make_medium<double>(view, tf);
  CHECK(m.value(Vec3(-1.0, 1.5, 2.0)) == Approx(f(Vec3(0.0, 1.5, 2.0))).margin(1e-12));
  CHECK(m.value(Vec3(3.5, -2.0, 9.0)) == Approx(f(Vec3(3.0, 0.0, 4.0))).margin(1e-12));
}

TEST_CASE("int16 linear fields with integer coefficients interpolate exactly", "[grid_medium]") {
  const Linear f{-300.0, 17.0, -11.0, 5.0};
  constexpr std::int64_t nx = 9, ny = 6, nz = 5;
  std::vector<std::int16_t> data(nx * ny * nz);
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        data[(k * ny + j) * nx + i] =
            static_cast<std::int16_t>(f(Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k))));
  const FieldView view = FieldView::contiguous(data.data(), tessera::DType::Int16, nx, ny, nz);
  tessera::TransferFunction tf;
  const auto m = make_medium<std::int16_t>(view, tf);
  tessera::Rng rng(8, 0, 0, 0);
  const std::int64_t n[3] = {nx, ny, nz};
  double worst = 0.0;
  for (int s = 0; s < 3000; ++s) {
    const Vec3 p = random_point(rng, n);
    worst = std::fmax(worst, std::fabs(m.value(p) - f(p)));
  }
  CHECK(worst < 1e-11);
}

TEST_CASE("gradient of u is exact on linear fields, inside and on the faces", "[grid_medium]") {
  const Linear f{0.5, 0.02, -0.03, 0.01};
  constexpr std::int64_t nx = 6, ny = 5, nz = 4;
  const std::vector<double> data = sample_linear(f, nx, ny, nz);
  const FieldView view = FieldView::contiguous(data.data(), tessera::DType::Float64, nx, ny, nz);
  tessera::TransferFunction tf;
  tf.lo = 0.0;  // u = v / 2: the field stays inside (0, 1) so the clamp never bites
  tf.hi = 2.0;
  const auto m = make_medium<double>(view, tf);
  tessera::Rng rng(9, 0, 0, 0);
  const std::int64_t n[3] = {nx, ny, nz};
  const Vec3 want(f.b / 2.0, f.c / 2.0, f.d / 2.0);
  double worst = 0.0;
  for (int s = 0; s < 2000; ++s) {
    const Vec3 g = m.gradient_voxel(random_point(rng, n));
    worst = std::fmax(worst, glm::length(g - want));
  }
  CHECK(worst < 1e-12);

  // A single vertex along an axis has no gradient along it
  const std::vector<double> flat = sample_linear(f, nx, ny, 1);
  const FieldView fv = FieldView::contiguous(flat.data(), tessera::DType::Float64, nx, ny, 1);
  const auto mf = make_medium<double>(fv, tf);
  const Vec3 g = mf.gradient_voxel(Vec3(2.5, 1.5, 0.0));
  CHECK(g.z == 0.0);
  CHECK(g.x == Approx(want.x).margin(1e-12));
}

TEST_CASE("non-finite vertices enter the interpolation as lo (NaN, -Inf) or hi (+Inf)", "[grid_medium]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  // 2 x 1 x 1: vertex 0 non-finite, vertex 1 = 3
  tessera::TransferFunction tf;
  tf.lo = -1.0;
  tf.hi = 5.0;
  for (const double bad : {nan, -inf, inf}) {
    const std::vector<float> data = {static_cast<float>(bad), 3.0f};
    const FieldView view = FieldView::contiguous(data.data(), tessera::DType::Float32, 2, 1, 1);
    const auto m = make_medium<float>(view, tf);
    const double mapped = bad > 0.0 ? tf.hi : tf.lo;
    CHECK(m.value(Vec3(0.0)) == mapped);
    CHECK(m.value(Vec3(0.25, 0.0, 0.0)) == Approx(0.75 * mapped + 0.25 * 3.0).margin(1e-12));
    CHECK(std::isfinite(m.u(Vec3(0.5, 0.0, 0.0))));
  }
  // NaN means "no medium": u == 0 exactly at the vertex
  const std::vector<float> data = {static_cast<float>(nan), 3.0f};
  const FieldView view = FieldView::contiguous(data.data(), tessera::DType::Float32, 2, 1, 1);
  tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  const auto m = make_medium<float>(view, tf);
  CHECK(m.u(Vec3(0.0)) == 0.0);
  CHECK(m.sigma_t(Vec3(0.0)) == 0.0);
}

TEST_CASE("the macrocell DDA visits the cells a ray crosses, in order, without gaps", "[grid_medium]") {
  // A medium whose "majorant" of each cell is the cell's linear index: the walk reports it.
  constexpr std::int64_t n[3] = {23, 17, 30};
  const std::vector<float> data(n[0] * n[1] * n[2], 0.0f);
  const FieldView view = FieldView::contiguous(data.data(), tessera::DType::Float32, n[0], n[1], n[2]);
  tessera::TransferFunction tf;
  tessera::Rng rng(10, 0, 0, 0);
  for (const int edge : {1, 3, 4, 8, 16, 64}) {
    tessera::GridMedium<float> m = make_medium<float>(view, tf);
    std::int64_t nc[3];
    for (int a = 0; a < 3; ++a) nc[a] = std::max<std::int64_t>(1, (n[a] - 1 + edge - 1) / edge);
    std::vector<double> ids(nc[0] * nc[1] * nc[2]);
    for (std::size_t c = 0; c < ids.size(); ++c) ids[c] = static_cast<double>(c);
    for (int a = 0; a < 3; ++a) m.nc[a] = nc[a];
    m.majorant = ids.data();
    m.cell_edge = edge;

    int bad_gap = 0, bad_cell = 0, bad_cover = 0, rays = 0;
    for (int r = 0; r < 400; ++r) {
      // Ray between two points of the box; some axis-aligned, some starting on cell faces.
      Vec3 a, b;
      for (int ax = 0; ax < 3; ++ax) {
        const double hi = static_cast<double>(n[ax] - 1);
        a[ax] = hi * rng.uniform();
        b[ax] = hi * rng.uniform();
        if (r % 4 == 1) a[ax] = std::floor(a[ax] / edge) * edge;  // start on a cell corner
      }
      if (r % 5 == 2) b.y = a.y, b.z = a.z;  // parallel to x
      if (r % 5 == 3) b.x = a.x;             // in a yz plane
      const double len = glm::length(b - a);
      if (len < 1e-6) continue;
      ++rays;
      const Vec3 dv = (b - a) / len;
      double t_prev = 0.0;
      tessera::traverse_macrocells(m, a, dv, 0.0, len, [&](double ta, double tb, double id) {
        if (ta != t_prev) ++bad_gap;
        t_prev = tb;
        // The segment's midpoint lies in the reported cell (closed box, rounding slack).
        const Vec3 mid = a + 0.5 * (ta + tb) * dv;
        const auto c = static_cast<std::int64_t>(id);
        const std::int64_t cell[3] = {c % nc[0], (c / nc[0]) % nc[1], c / (nc[0] * nc[1])};
        for (int ax = 0; ax < 3; ++ax) {
          const double lo = static_cast<double>(cell[ax] * edge) - 1e-9;
          const double hi = static_cast<double>((cell[ax] + 1) * edge) + 1e-9;
          if (mid[ax] < lo || mid[ax] > hi) {
            ++bad_cell;
            break;
          }
        }
        return false;
      });
      if (std::fabs(t_prev - len) > 1e-9 * len) ++bad_cover;
    }
    INFO("edge " << edge << ", rays " << rays);
    CHECK(bad_gap == 0);
    CHECK(bad_cell == 0);
    CHECK(bad_cover == 0);
  }
}

TEST_CASE("the gradient equals central differences of u on random fields, NaN and Inf vertices included",
          "[grid_medium]") {
  // Random int16 and float fields (the float one with NaN and +-Inf vertices); points all over
  // the box, inside (p +- 1 inside the samples) and near the faces (one-sided), against
  // (u(p + e_a) - u(p - e_a)) / h computed here.
  constexpr std::int64_t nx = 9, ny = 7, nz = 6;
  tessera::Rng rng(21, 0, 0, 0);
  std::vector<std::int16_t> i16(nx * ny * nz);
  std::vector<float> f32(nx * ny * nz);
  for (std::size_t q = 0; q < i16.size(); ++q) {
    i16[q] = static_cast<std::int16_t>(rng.uniform() * 60000.0 - 30000.0);
    const double r = rng.uniform();
    f32[q] = r < 0.02   ? std::numeric_limits<float>::quiet_NaN()
             : r < 0.03 ? std::numeric_limits<float>::infinity()
             : r < 0.04 ? -std::numeric_limits<float>::infinity()
                        : static_cast<float>(rng.uniform() * 4.0 - 1.0);
  }
  tessera::TransferFunction ti, tf;
  ti.lo = -20000.0;  // some values clamp at u = 0 and 1
  ti.hi = 25000.0;
  tf.lo = -0.5;
  tf.hi = 2.5;
  const auto mi = make_medium<std::int16_t>(FieldView::contiguous(i16.data(), tessera::DType::Int16, nx, ny, nz), ti);
  const auto mf = make_medium<float>(FieldView::contiguous(f32.data(), tessera::DType::Float32, nx, ny, nz), tf);
  const std::int64_t n[3] = {nx, ny, nz};
  int interior = 0;
  const auto central = [](const auto& m, const Vec3& p) {
    Vec3 g(0.0);
    for (int a = 0; a < 3; ++a) {
      Vec3 pm = p, pp = p;
      pm[a] = std::clamp(p[a] - 1.0, 0.0, m.hi_index[a]);
      pp[a] = std::clamp(p[a] + 1.0, 0.0, m.hi_index[a]);
      if (pp[a] > pm[a]) g[a] = (m.u(pp) - m.u(pm)) / (pp[a] - pm[a]);
    }
    return g;
  };
  double worst = 0.0;
  for (int s = 0; s < 4000; ++s) {
    const Vec3 p = random_point(rng, n);
    bool inside = true;
    for (int a = 0; a < 3; ++a) inside = inside && p[a] >= 1.0 && p[a] + 1.0 < mi.hi_index[a];
    interior += inside;
    worst = std::fmax(worst, glm::length(mi.gradient_voxel(p) - central(mi, p)));
    worst = std::fmax(worst, glm::length(mf.gradient_voxel(p) - central(mf, p)));
  }
  CHECK(interior > 300);
  CHECK(worst < 1e-12);
}
