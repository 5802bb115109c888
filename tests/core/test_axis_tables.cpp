// The rectilinear axes' tables (scene/axis_tables.h) and checks: a lookup finds the segment a
// search over the knots would, with the bin table capped or not; the memory estimate counts
// the tables prepare builds; bad coordinates are refused naming the axis and index.
#include <tessera/memory_estimate.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "sampling/rng.h"
#include "scene/axis_tables.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

using tessera::Association;
using tessera::FieldView;
using tessera::Vec3;

namespace {

std::string prepare_error(const FieldView& view, const tessera::SceneDesc& s) {
  try {
    tessera::prepare(view, s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("an axis lookup finds the segment a search would, the bin table capped or not", "[rectilinear][axis]") {
  // Against std::upper_bound over the knots, for mild and extreme stretching (a 1e-6 interval
  // next to unit ones, or intervals growing 1.1x per knot, cap the bin table at 4 (n - 1) + 64
  // entries, so a bin may hold many knots and the lookup searches inside it), vertex and cell
  // data, and points on the knots.
  tessera::Rng rng(17, 0, 0, 0);
  for (const bool cell : {false, true})
    for (const double ratio : {1.0, 1.005, 0.985, 1.1, 1e-6}) {  // interval i: ratio^i (1e-6: see below)
      const std::int64_t n = 200;                                // knots
      std::vector<double> c(static_cast<std::size_t>(n + (cell ? 1 : 0)));
      double x = -3.0;
      for (std::size_t i = 0; i < c.size(); ++i) {
        c[i] = x;
        x += ratio == 1e-6 ? (i % 50 == 7 ? 1e-6 : 1.0) : std::pow(ratio, double(i));
      }
      std::vector<float> field(static_cast<std::size_t>(n), 0.0f);
      const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, 1, 1);
      tessera::VolumeGeometry g{Vec3(0.0), Vec3(1.0), cell ? Association::Cell : Association::Vertex};
      g.coords[0] = c.data();
      const std::int64_t nc[3] = {(n - 1 + 3) / 4, 1, 1};
      tessera::AxisTables tables;
      tables.build(view, g, 4, nc);
      const tessera::AxisMap& m = tables.map(0);
      REQUIRE(m.coords == c.data());  // read in place
      std::vector<double> knots(static_cast<std::size_t>(n));
      for (std::int64_t i = 0; i < n; ++i) knots[static_cast<std::size_t>(i)] = m.knot(i);
      // Capped tables: 1e-6 intervals (vertex data; cell centres stay 0.5 apart), and 1.1^i
      // (1.7e8 between the smallest and largest interval: the first bin holds most knots)
      if ((ratio == 1e-6 && !cell) || ratio == 1.1) CHECK(m.nbins == 4 * (n - 1) + 64);
      CHECK(tables.bytes() <= tessera::axis_table_bytes(view, g, 4));
      int wrong = 0;
      for (int k = 0; k < 20000; ++k) {
        double p = knots.front() + (knots.back() - knots.front()) * rng.uniform();
        if (k % 5 == 0) p = knots[static_cast<std::size_t>(rng.uniform() * n)];  // on a knot
        if (k % 97 == 0) p = knots.front() - 1.0;                                // clamped
        std::int64_t seg;
        double f;
        m.locate(p, &seg, &f);
        const double pc = std::clamp(p, knots.front(), knots.back());
        auto it = std::upper_bound(knots.begin(), knots.end(), pc);
        std::int64_t want = std::clamp<std::int64_t>((it - knots.begin()) - 1, 0, n - 2);
        const double fw = (pc - knots[static_cast<std::size_t>(want)]) /
                          (knots[static_cast<std::size_t>(want) + 1] - knots[static_cast<std::size_t>(want)]);
        // A point on a knot is the end of one segment or the start of the next: same value
        const bool ok = (seg == want && std::fabs(f - fw) <= 1e-12) ||
                        (seg == want - 1 && pc == knots[static_cast<std::size_t>(want)] && f == 1.0);
        wrong += ok ? 0 : 1;
      }
      INFO((cell ? "cell" : "vertex") << ", ratio " << ratio << ", bins " << m.nbins);
      CHECK(wrong == 0);
    }
}

TEST_CASE("the memory estimate counts the rectilinear axes' tables as prepare builds them", "[rectilinear][memory]") {
  const std::vector<float> field(static_cast<std::size_t>(40 * 1 * 9), 0.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 40, 1, 9);
  std::vector<double> x(41), y(2), z(10);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = 0.01 * static_cast<double>(i * i);
  y = {0.0, 1.0};
  for (std::size_t i = 0; i < z.size(); ++i) z[i] = static_cast<double>(i);
  for (const bool cell : {false, true}) {
    tessera::VolumeGeometry g{Vec3(0.0), Vec3(1.0), cell ? Association::Cell : Association::Vertex};
    g.coords[0] = x.data();
    g.coords[1] = cell ? y.data() : nullptr;  // one cell: two boundaries
    g.coords[2] = z.data();
    tessera::RenderFootprint f;
    f.width = f.height = 8;
    for (int a = 0; a < 3; ++a) {
      f.field_dims[a] = view.dims[a];
      f.rectilinear[a] = g.coords[a] != nullptr;
    }
    f.macrocell_edge = 4;
    std::uint64_t part = 0;
    for (const auto& p : tessera::estimate_render_memory(f).parts)
      if (p.name == "axis tables") part = p.bytes;
    CHECK(part == tessera::axis_table_bytes(view, g, 4));
    const std::int64_t nc[3] = {10, 1, 2};
    tessera::AxisTables tables;
    tables.build(view, g, 4, nc);
    CHECK(tables.bytes() > 0);
    CHECK(tables.bytes() <= part);
  }
}

TEST_CASE("bad coordinates are refused naming the axis and index", "[rectilinear][validation]") {
  const std::vector<float> field(4 * 3 * 5, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 4, 3, 5);
  tessera::SceneDesc s;
  s.camera.position = Vec3(0.0, 0.0, -10.0);
  std::vector<double> y = {0.0, 1.0, 1.0};
  s.geometry.coords[1] = y.data();
  CHECK(prepare_error(view, s) ==
        "rectilinear axis y (3 vertex coordinates): coordinate 2 (1) is not above coordinate 1 (1), coordinates must "
        "be strictly increasing");
  y = {0.0, 2.0, 1.0};
  CHECK(prepare_error(view, s).find("coordinate 2 (1) is not above coordinate 1 (2)") != std::string::npos);
  y = {0.0, std::numeric_limits<double>::quiet_NaN(), 1.0};
  CHECK(prepare_error(view, s) ==
        "rectilinear axis y (3 vertex coordinates): coordinate 1 is NaN, coordinates must be finite");
  y = {0.0, 1.0, INFINITY};
  CHECK(prepare_error(view, s).find("coordinate 2 is ") != std::string::npos);
  // Cell data: dims + 1 boundaries
  s.geometry.coords[1] = nullptr;
  s.geometry.association = Association::Cell;
  std::vector<double> z = {0.0, 0.5, 1.0, 1.5, 2.0, 1.9};
  s.geometry.coords[2] = z.data();
  CHECK(prepare_error(view, s) ==
        "rectilinear axis z (6 cell boundaries): coordinate 5 (1.9) is not above coordinate 4 (2), coordinates must "
        "be strictly increasing");
  z.back() = 2.5;
  CHECK(prepare_error(view, s).empty());
  // Scale: the smallest interval counts (2^40 smallest spacings)
  z = {0.0, 1e-12, 1.0, 1.5, 2.0, 2.5};
  s.geometry.origin = Vec3(1e3, 0.0, 0.0);
  CHECK(prepare_error(view, s).find("beyond 2^40 smallest spacings") != std::string::npos);
}
