// Tests for MajorantGrid: the majorant of every macrocell bounds the extinction of the
// trilinear field everywhere in the cell, faces and the +1 vertex overlap included, for random
// fields (NaN / Inf vertices, integer dtypes) and random piecewise-linear opacity TFs; in grid
// and global mode; and along the cells the DDA reports for random rays.
#include <catch2/catch.hpp>

#include "field/majorant_grid.h"
#include "kernel/grid_medium.h"
#include "sampling/rng.h"
#include "scene/prepared_scene_impl.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <vector>

using tessera::FieldView;
using tessera::MajorantGrid;
using tessera::TransferFunction;
using tessera::Vec3;

namespace {

/// Random field storage of one dtype; floats get NaN / +Inf / -Inf vertices sprinkled in.
struct RandomField {
  std::vector<unsigned char> bytes;
  FieldView view;
  double lo, hi;  ///< a TF range that covers part of the values
};

template <class T>
RandomField make_random_field(tessera::Rng& rng, const std::int64_t n[3], bool non_finite) {
  RandomField f;
  const std::int64_t count = n[0] * n[1] * n[2];
  f.bytes.resize(static_cast<std::size_t>(count) * sizeof(T));
  double vmin, vmax;
  if constexpr (std::is_floating_point_v<T>) vmin = -1.0, vmax = 2.0;
  else if constexpr (std::is_signed_v<T>) vmin = -1000.0, vmax = 1000.0;
  else vmin = 0.0, vmax = 255.0;
  for (std::int64_t i = 0; i < count; ++i) {
    T v;
    const double r = rng.uniform();
    if constexpr (std::is_floating_point_v<T>) {
      if (non_finite && r < 0.03) v = std::numeric_limits<T>::quiet_NaN();
      else if (non_finite && r < 0.045) v = std::numeric_limits<T>::infinity();
      else if (non_finite && r < 0.06) v = -std::numeric_limits<T>::infinity();
      else v = static_cast<T>(vmin + (vmax - vmin) * rng.uniform());
    } else {
      v = static_cast<T>(std::floor(vmin + (vmax - vmin + 1.0) * rng.uniform()));
    }
    std::memcpy(&f.bytes[static_cast<std::size_t>(i) * sizeof(T)], &v, sizeof(T));
  }
  f.view = FieldView::contiguous(f.bytes.data(), tessera_test::dtype_of<T>(), n[0], n[1], n[2]);
  // TF range: a random sub-interval of the values, sometimes wider than them.
  const double a = vmin + (vmax - vmin) * (1.4 * rng.uniform() - 0.2);
  const double b = vmin + (vmax - vmin) * (1.4 * rng.uniform() - 0.2);
  f.lo = std::min(a, b);
  f.hi = std::max(a, b) + 1e-3 * (vmax - vmin);
  return f;
}

/// Random piecewise-linear opacity: 1..8 points, some outside [0, 1], some steps (equal x),
/// some zero stretches.
tessera::ScalarTF random_opacity(tessera::Rng& rng) {
  const int np = 1 + static_cast<int>(rng.uniform() * 8.0);
  std::vector<double> xs(np), vs(np);
  for (int i = 0; i < np; ++i) {
    xs[i] = 1.4 * rng.uniform() - 0.2;
    vs[i] = rng.uniform() < 0.25 ? 0.0 : rng.uniform();
  }
  std::sort(xs.begin(), xs.end());
  if (np > 2 && rng.uniform() < 0.5) xs[1] = xs[2];  // a step
  return tessera::ScalarTF(xs, vs);
}

/// Sample points of macrocell c along one axis: its closed interval in voxel space, clipped
/// to the box, with the faces themselves (the +1 overlap) always included.
struct Interval {
  double lo, hi;
};
Interval cell_interval(std::int64_t c, int edge, std::int64_t n) {
  const double hi_box = static_cast<double>(n - 1);
  return {std::min(static_cast<double>(c) * edge, hi_box), std::min(static_cast<double>(c + 1) * edge, hi_box)};
}
double pick(tessera::Rng& rng, const Interval& iv) {
  const double r = rng.uniform();
  if (r < 0.2) return iv.lo;
  if (r < 0.4) return iv.hi;
  if (r < 0.55) {  // a vertex inside the cell
    const double k = std::floor(iv.lo + rng.uniform() * (iv.hi - iv.lo + 1.0));
    return std::min(k, iv.hi);
  }
  return iv.lo + (iv.hi - iv.lo) * rng.uniform();
}

/// Densely checks sigma_t(p) <= majorant(cell) for points of every cell. Returns the number
/// of violations and describes the first one in *first.
template <class T>
int count_violations(const FieldView& view, const TransferFunction& tf, const MajorantGrid& grid, tessera::Rng& rng,
                     int points_per_cell, std::string* first) {
  const auto m = tessera_test::make_medium<T>(view, tf, &grid);
  const std::int64_t* nc = grid.cells();
  int bad = 0;
  for (std::int64_t cz = 0; cz < nc[2]; ++cz)
    for (std::int64_t cy = 0; cy < nc[1]; ++cy)
      for (std::int64_t cx = 0; cx < nc[0]; ++cx) {
        const double maj = grid.majorants()[grid.cell_index(cx, cy, cz)];
        const Interval ix = cell_interval(cx, grid.edge(), view.dims[0]);
        const Interval iy = cell_interval(cy, grid.edge(), view.dims[1]);
        const Interval iz = cell_interval(cz, grid.edge(), view.dims[2]);
        for (int s = 0; s < points_per_cell; ++s) {
          Vec3 p(pick(rng, ix), pick(rng, iy), pick(rng, iz));
          if (s < 8) p = Vec3(s & 1 ? ix.hi : ix.lo, s & 2 ? iy.hi : iy.lo, s & 4 ? iz.hi : iz.lo);
          const double sigma = m.sigma_t(p);
          if (!(sigma <= maj)) {
            if (bad++ == 0 && first) {
              std::ostringstream os;
              os.precision(17);
              os << "cell (" << cx << "," << cy << "," << cz << ") p=(" << p.x << "," << p.y << "," << p.z
                 << ") sigma_t=" << sigma << " majorant=" << maj;
              *first = os.str();
            }
          }
        }
      }
  return bad;
}

/// Same bound along the segments the DDA reports for random rays through the box.
template <class T>
int count_ray_violations(const FieldView& view, const TransferFunction& tf, const MajorantGrid& grid, tessera::Rng& rng,
                         int rays) {
  const auto m = tessera_test::make_medium<T>(view, tf, &grid);
  int bad = 0;
  for (int r = 0; r < rays; ++r) {
    Vec3 a, b;
    for (int ax = 0; ax < 3; ++ax) {
      const double hi = static_cast<double>(view.dims[ax] - 1);
      a[ax] = hi * rng.uniform();
      b[ax] = hi * rng.uniform();
    }
    const double len = glm::length(b - a);
    if (!(len > 1e-9)) continue;
    const Vec3 dv = (b - a) / len;
    tessera::traverse_macrocells(m, a, dv, 0.0, len, [&](double ta, double tb, double maj) {
      for (int s = 0; s < 6; ++s) {
        const double t = s == 0 ? ta : (s == 1 ? tb : ta + (tb - ta) * rng.uniform());
        if (!(m.sigma_t(a + t * dv) <= maj)) ++bad;
      }
      return false;
    });
  }
  return bad;
}

template <class T>
void check_random_fields(std::uint64_t seed, bool non_finite, int trials) {
  tessera::Rng rng(seed, 0, 0, 0);
  for (int trial = 0; trial < trials; ++trial) {
    std::int64_t n[3];
    for (int a = 0; a < 3; ++a) n[a] = 1 + static_cast<std::int64_t>(rng.uniform() * 19.0);
    if (trial % 7 == 3) n[trial % 3] = 2;  // degenerate axes now and then
    if (trial % 7 == 5) n[(trial + 1) % 3] = 1;
    const RandomField f = make_random_field<T>(rng, n, non_finite);
    TransferFunction tf;
    tf.lo = f.lo;
    tf.hi = f.hi;
    tf.density_scale = 0.1 + 50.0 * rng.uniform();
    tf.opacity = random_opacity(rng);
    const std::int64_t max_dim = std::max({n[0], n[1], n[2]});
    for (const int edge : {1, 2, 3, 5, 16, static_cast<int>(max_dim)}) {
      MajorantGrid grid;
      grid.build(f.view, edge);
      grid.update(tf);
      std::string first;
      const int bad = count_violations<T>(f.view, tf, grid, rng, 40, &first);
      const int bad_rays = count_ray_violations<T>(f.view, tf, grid, rng, 30);
      INFO("seed " << seed << " trial " << trial << " dims " << n[0] << "x" << n[1] << "x" << n[2] << " edge " << edge
                   << " tf range [" << tf.lo << ", " << tf.hi << "] " << first);
      REQUIRE(bad == 0);
      REQUIRE(bad_rays == 0);
    }
  }
}

}  // namespace

TEST_CASE("majorant >= sigma_t everywhere in every macrocell, random fields and TFs", "[majorant_grid]") {
  SECTION("float32 with NaN and +-Inf vertices") { check_random_fields<float>(101, true, 25); }
  SECTION("float64 with NaN and +-Inf vertices") { check_random_fields<double>(102, true, 10); }
  SECTION("int16") { check_random_fields<std::int16_t>(103, false, 20); }
  SECTION("uint8") { check_random_fields<std::uint8_t>(104, false, 10); }
  SECTION("uint16") { check_random_fields<std::uint16_t>(105, false, 5); }
}

TEST_CASE("majorant on a linear ramp is tight and respects the +1 vertex overlap", "[majorant_grid]") {
  // v = i along x over 9 vertices, opacity = u, range [0, 8]: with edge 4 cell 0 spans
  // vertices 0..4, cell 1 vertices 4..8 (vertex 4 shared).
  std::vector<float> data(9 * 2 * 2);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 9; ++i) data[(k * 2 + j) * 9 + i] = static_cast<float>(i);
  const FieldView view = FieldView::contiguous(data.data(), tessera::DType::Float32, 9, 2, 2);
  TransferFunction tf;
  tf.lo = 0.0;
  tf.hi = 8.0;
  tf.density_scale = 3.0;
  tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  MajorantGrid grid;
  grid.build(view, 4);
  grid.update(tf);
  REQUIRE(grid.cells()[0] == 2);
  REQUIRE(grid.cells()[1] == 1);
  REQUIRE(grid.cells()[2] == 1);
  // Cell 0 max value 4 (its +1 vertex), u = 0.5: majorant 1.5; cell 1 max u = 1: majorant 3.
  CHECK(grid.majorants()[0] == Approx(1.5).epsilon(1e-8));
  CHECK(grid.majorants()[0] >= 1.5);
  CHECK(grid.majorants()[1] == Approx(3.0).epsilon(1e-8));
  CHECK(grid.max_majorant() == grid.majorants()[1]);
  CHECK(grid.value_min() == 0.0);
  CHECK(grid.value_max() == 8.0);

  // An opacity that is 0 up to u = 0.5 makes cell 0 (u in [0, 0.5], its +1 vertex included)
  // empty: majorant exactly 0, so delta tracking crosses it in closed form.
  tf.opacity = tessera::ScalarTF({0.5, 1.0}, {0.0, 1.0});
  grid.update(tf);
  CHECK(grid.majorants()[0] == 0.0);
  CHECK(grid.majorants()[1] > 0.0);
}

TEST_CASE("update() after a TF change equals a fresh build, and global mode is one cell", "[majorant_grid]") {
  tessera::Rng rng(55, 0, 0, 0);
  const std::int64_t n[3] = {13, 9, 11};
  const RandomField f = make_random_field<float>(rng, n, true);
  TransferFunction tf1, tf2;
  tf1.lo = tf2.lo = f.lo;
  tf1.hi = tf2.hi = f.hi;
  tf1.opacity = random_opacity(rng);
  tf2.opacity = random_opacity(rng);
  tf2.density_scale = 7.0;
  MajorantGrid reused;
  reused.build(f.view, 4);
  reused.update(tf1);
  reused.update(tf2);
  MajorantGrid fresh;
  fresh.build(f.view, 4);
  fresh.update(tf2);
  const std::int64_t ncell = fresh.cells()[0] * fresh.cells()[1] * fresh.cells()[2];
  bool same = true;
  for (std::int64_t c = 0; c < ncell; ++c) same = same && reused.majorants()[c] == fresh.majorants()[c];
  CHECK(same);

  // NaN count
  std::uint64_t nans = 0;
  for (std::int64_t i = 0; i < n[0] * n[1] * n[2]; ++i) {
    float v;
    std::memcpy(&v, &f.bytes[i * 4], 4);
    nans += std::isnan(v) ? 1 : 0;
  }
  CHECK(fresh.nan_vertices() == nans);
  CHECK(nans > 0);

  // Global mode through prepare(): a single cell bounding every vertex's extinction
  tessera::SceneDesc scene;
  scene.tf = tf2;
  scene.integrator.majorant = tessera::MajorantMode::Global;
  scene.image = {4, 4, 1, 0.0};
  const tessera::PreparedScene ps = tessera::prepare(f.view, scene);
  const MajorantGrid& g = prepared_scene_impl(ps).grid;
  CHECK(g.cells()[0] == 1);
  CHECK(g.cells()[1] == 1);
  CHECK(g.cells()[2] == 1);
  std::string first;
  CHECK(count_violations<float>(f.view, tf2, g, rng, 20000, &first) == 0);
  INFO(first);
  CHECK(g.max_majorant() >= fresh.max_majorant() * (1.0 - 1e-12));

  CHECK_THROWS_WITH(fresh.build(f.view, 0), Catch::Contains("edge"));
}
