// A mesh's macrocell summary folded in the input's order over the layout's kept macrocell
// spans (mesh/macro_spans.h): bit for bit the fold of every element in the layout's canonical
// order (what a device does: cuda/mesh_device.h) with each element's range taken value by
// value, on one thread or several, for any macrocell edge, with ghosts, NaN, infinities and
// -0.0 among the values; the spans made once per grid and kept with the layout.
#include <tessera/render.h>

#include <catch2/catch.hpp>
#include <tbb/task_arena.h>

#include "mesh/macro_spans.h"
#include "mesh/mesh_layout.h"
#include "mesh/mesh_summary.h"
#include "mesh/mesh_tables.h"
#include "test_mesh_support.h"
#include "test_support.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

using namespace tessera_mesh_test;

namespace {

/// A warped 40 x 36 x 30 hex grid (43,200 cells: enough for the fold's threads) cut into
/// three domains listed out of order, one with int64 indices and its cells reversed, a tenth
/// of one domain's cells ghosts; values with NaN, +-Inf and -0.0 among them.
struct CutGrid {
  OwnedMesh owned;
  std::vector<std::uint8_t> mask;

  /// `domains` > 3: the cells dealt round-robin over that many domains (no ghosts).
  explicit CutGrid(tessera::Association association, int domains = 3) {
    ElementList m = grid_hexes(
        40, 36, 30, Vec3(0.0), Vec3(1.0 / 40, 1.0 / 36, 1.0 / 30),
        [](const Vec3& p) { return std::sin(7.0 * p.x) * std::cos(5.0 * p.y + 3.0 * p.z); },
        [](const Vec3& p) { return Vec3(p.x + 0.1 * p.y * p.z, p.y + 0.05 * p.x, p.z); });
    if (association == tessera::Association::Cell) {
      m.association = association;
      m.value.assign(m.element.size(), 0.0);
      for (std::size_t e = 0; e < m.value.size(); ++e) m.value[e] = std::cos(0.013 * static_cast<double>(e));
    }
    m.value[17] = NAN;
    m.value[901] = INFINITY;
    m.value[2500] = -INFINITY;
    m.value[40] = -0.0;
    std::vector<int> part(m.element.size());
    if (domains > 3) {
      for (std::size_t e = 0; e < part.size(); ++e)
        part[e] = static_cast<int>((e * 7) % static_cast<std::size_t>(domains));
      std::vector<int> order(static_cast<std::size_t>(domains));
      for (int d = 0; d < domains; ++d) order[static_cast<std::size_t>(d)] = domains - 1 - d;
      owned = cut(m, part, order);
      return;
    }
    for (std::size_t e = 0; e < part.size(); ++e) part[e] = e < 15000 ? 0 : (e < 30000 ? 1 : 2);
    owned = cut(m, part, {2, 0, 1}, true, true);
    tessera::MeshDomain& d = owned.mesh.domains[1];
    mask.assign(static_cast<std::size_t>(d.cell_count()), 0);
    for (std::size_t c = 0; c < mask.size(); c += 10) mask[c] = 1;
    d.ghosts = {mask.data(), 1, static_cast<std::int64_t>(mask.size())};
  }
};

/// Element `ref`'s range value by value (add_value), not by element_range's fast path.
tessera::ElementRange range_by_value(const tessera::DomainAccess* domains, const tessera::MeshElementRef& ref) {
  const tessera::DomainAccess& d = domains[ref.domain];
  tessera::ElementRange r;
  if (d.cell_data) {
    tessera::add_value(r, d.value(ref.cell));
    return r;
  }
  std::int64_t idx[8];
  d.cell_vertices(ref.cell, idx);
  for (int k = 0; k < d.nv; ++k) tessera::add_value(r, d.value(idx[k]));
  return r;
}

/// The macrocells of `t` folded element by element in the layout's canonical order.
tessera::FieldSummary::Parts canonical_fold(const tessera::MeshTables& t, const tessera::MacroGrid& g) {
  tessera::FieldSummary::Parts parts = tessera::empty_cells(g);
  for (std::size_t e = 0; e < t.element_count(); ++e)
    tessera::fold_into_cells(parts, g, t.box(e), range_by_value(t.domains().data(), t.layout()->element(e)));
  return parts;
}

/// Whether summary `s`'s cells are `p`'s, bit for bit.
bool same_cells(const tessera::FieldSummary& s, const tessera::FieldSummary::Parts& p) {
  const auto r = s.ranges();
  if (r.size() != p.lo.size()) return false;
  for (std::size_t c = 0; c < r.size(); ++c) {
    const std::uint8_t flags =
        static_cast<std::uint8_t>((r[c].nan ? 1 : 0) | (r[c].pos_inf ? 2 : 0) | (r[c].neg_inf ? 4 : 0));
    if (std::memcmp(&r[c].lo, &p.lo[c], sizeof(double)) != 0 || std::memcmp(&r[c].hi, &p.hi[c], sizeof(double)) != 0 ||
        flags != p.flags[c])
      return false;
  }
  return true;
}

/// A small scene over the test meshes (macrocell edge 5).
tessera::SceneDesc share_scene() {
  tessera::SceneDesc s;
  s.tf.lo = -1.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = 6.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  s.camera.position = Vec3(0.5, 0.5, -2.0);
  s.camera.look_at = Vec3(0.5);
  s.image = {16, 12, 2, 0.0};
  s.integrator.macrocell = 5;
  return s;
}

}  // namespace

TEST_CASE("mesh summary: folded in the input's order, the macrocells are the canonical order's, bit for bit",
          "[mesh][summary]") {
  for (const tessera::Association association : {tessera::Association::Vertex, tessera::Association::Cell}) {
    const CutGrid grid(association);
    tessera::MeshTables t;
    t.build(grid.owned.mesh);
    REQUIRE(t.element_count() == 43200u - 1500u);  // the ghosts left out
    const std::int64_t max_dim = std::max({t.dims()[0], t.dims()[1], t.dims()[2]});
    for (const int edge : {1, 3, 8, static_cast<int>(max_dim)}) {
      INFO("association " << static_cast<int>(association) << ", edge " << edge);
      const tessera::MacroGrid g = tessera::macro_grid(t.geometry(), t.dims(), edge);
      const tessera::FieldSummary::Parts want = canonical_fold(t, g);
      for (const int threads : {1, 2}) {
        tbb::task_arena arena(threads);
        const auto s = arena.execute([&] { return tessera::mesh_summary(t, edge); });
        CHECK(same_cells(*s, want));
      }
    }
  }
}

TEST_CASE("mesh summary: over hundreds of domains, each thread's share found by its first cell's domain",
          "[mesh][summary]") {
  const CutGrid grid(tessera::Association::Vertex, 401);
  tessera::MeshTables t;
  t.build(grid.owned.mesh);
  REQUIRE(t.element_count() == 43200u);
  const tessera::MacroGrid g = tessera::macro_grid(t.geometry(), t.dims(), 4);
  const auto spans = t.layout()->macro_spans(g);
  REQUIRE(spans->domain_count() == 401u);
  for (std::size_t d = 0; d < 401; ++d) {
    CHECK(spans->domain_of(static_cast<std::size_t>(spans->offset(d))) == d);
    CHECK(spans->domain_of(static_cast<std::size_t>(spans->offset(d + 1)) - 1) == d);
  }
  const tessera::FieldSummary::Parts want = canonical_fold(t, g);
  for (const int threads : {1, 2}) {
    tbb::task_arena arena(threads);
    CHECK(same_cells(*arena.execute([&] { return tessera::mesh_summary(t, 4); }), want));
  }
}

TEST_CASE("mesh layout: the macrocell spans are made once per grid, kept and counted", "[mesh][summary]") {
  const CutGrid grid(tessera::Association::Vertex);
  tessera::MeshTables t;
  t.build(grid.owned.mesh);
  const auto& layout = t.layout();
  const std::uint64_t bare = layout->bytes();
  const tessera::MacroGrid g8 = tessera::macro_grid(t.geometry(), t.dims(), 8);
  const auto spans = layout->macro_spans(g8);
  CHECK(layout->bytes() == bare + spans->bytes());
  CHECK(layout->macro_spans(g8) == spans);  // kept
  REQUIRE(spans->domain_count() == 3u);
  REQUIRE(spans->all().size() == 43200u);
  // Every element's span is where its input cell lies, and is its box's macrocells
  std::vector<bool> element(spans->all().size(), false);
  for (std::size_t e = 0; e < layout->element_count(); ++e) {
    const tessera::MeshElementRef& ref = layout->element(e);
    const auto i = static_cast<std::size_t>(spans->offset(static_cast<std::size_t>(ref.domain)) + ref.cell);
    element[i] = true;
    std::int64_t c0[3], c1[3];
    g8.span(layout->box(e), c0, c1);
    const tessera::MacroSpan& s = spans->all()[i];
    CHECK(s.first == (c0[2] * g8.cells[1] + c0[1]) * g8.cells[0] + c0[0]);
    for (int a = 0; a < 3; ++a) CHECK(s.n[a] == static_cast<std::uint32_t>(c1[a] - c0[a] + 1));
  }
  // Every other cell (the ghosts of domain 1, listed second) has none
  std::size_t none = 0;
  for (std::size_t i = 0; i < element.size(); ++i)
    if (!element[i]) {
      ++none;
      CHECK(spans->all()[i].n[0] == 0u);
      CHECK(i >= static_cast<std::size_t>(spans->offset(1)));
      CHECK(i < static_cast<std::size_t>(spans->offset(2)));
    }
  CHECK(none == 1500u);
  // Another grid replaces them; the first grid again is made again
  const tessera::MacroGrid g4 = tessera::macro_grid(t.geometry(), t.dims(), 4);
  const auto other = layout->macro_spans(g4);
  CHECK(other != spans);
  CHECK(layout->bytes() == bare + other->bytes());
  CHECK(layout->macro_spans(g8) != other);
  CHECK(layout->macro_spans(g8)->over(g8));
}

TEST_CASE("mesh layout: a prepare that reuses the layout reads the spans an earlier prepare made", "[mesh][summary]") {
  CutGrid grid(tessera::Association::Vertex);
  tessera::SceneDesc s = share_scene();
  s.integrator.macrocell = 6;
  for (auto& od : grid.owned.owned)  // finite values: the scene's range check passes
    for (double& v : od->values)
      if (!std::isfinite(v)) v = 0.25;
  const tessera::PreparedScene first = tessera::prepare(grid.owned.mesh, s);
  const auto& layout = first.mesh_layout();
  const tessera::MacroGrid g = tessera::macro_grid(layout->geometry(), layout->dims(), 6);
  const std::uint64_t with_spans = layout->bytes();
  const auto made = layout->macro_spans(g);
  CHECK(layout->bytes() == with_spans);  // made by the prepare, not by this call
  for (auto& od : grid.owned.owned)
    for (double& v : od->values) v = -v;
  const tessera::PreparedScene second = tessera::prepare(grid.owned.mesh, s, layout);
  CHECK(second.mesh_layout_reused());
  CHECK(layout->macro_spans(g) == made);
}

TEST_CASE("mesh summary: shares over 1 to 7 ranks combine into the whole summary and render the same bits",
          "[mesh][summary]") {
  CutGrid grid(tessera::Association::Vertex);
  const tessera::Mesh& mesh = grid.owned.mesh;
  const tessera::SceneDesc s = share_scene();
  const tessera::PreparedScene built = tessera::prepare(mesh, s);
  const auto& layout = built.mesh_layout();
  const tessera::Film want = tessera_test::render_film(tessera::prepare(mesh, s, layout));
  tessera::MeshTables t;
  t.build(mesh, layout);
  const auto whole = tessera::mesh_summary(t, 5);
  const tessera::MeshChecked checked = tessera::check_mesh_indices(mesh);
  for (const int n : {1, 2, 3, 7}) {
    INFO(n << " shares");
    tessera::FieldSummary::Parts parts = tessera::mesh_summary_parts(mesh, s, layout, checked, 0, n);
    for (int r = 1; r < n; ++r)
      tessera::FieldSummary::combine(parts, tessera::mesh_summary_parts(mesh, s, layout, checked, r, n));
    const auto summary = tessera::mesh_summary_of_parts(std::move(parts), mesh, s, layout);
    REQUIRE(summary->ranges().size() == whole->ranges().size());
    for (std::size_t c = 0; c < whole->ranges().size(); ++c) {
      const tessera::CellRange &a = summary->ranges()[c], &b = whole->ranges()[c];
      CHECK(std::memcmp(&a.lo, &b.lo, sizeof(double)) == 0);
      CHECK(std::memcmp(&a.hi, &b.hi, sizeof(double)) == 0);
      CHECK((a.nan == b.nan && a.pos_inf == b.pos_inf && a.neg_inf == b.neg_inf));
    }
    CHECK(summary->nan_vertices() == whole->nan_vertices());
    CHECK(summary->element_count() == whole->element_count());
    const double lo[2] = {summary->value_min(), whole->value_min()}, hi[2] = {summary->value_max(), whole->value_max()};
    CHECK(std::memcmp(&lo[0], &lo[1], sizeof(double)) == 0);
    CHECK(std::memcmp(&hi[0], &hi[1], sizeof(double)) == 0);
    const tessera::Film got = tessera_test::render_film(tessera::prepare(mesh, s, layout, checked, summary));
    CHECK(std::memcmp(got.pixels().data(), want.pixels().data(), want.pixels().size() * sizeof(tessera::PixelSums)) ==
          0);
  }
  // Refused by name: a share out of range, no layout, a summary of another macrocell edge
  CHECK_THROWS_WITH(tessera::mesh_summary_parts(mesh, s, layout, checked, 3, 3), Catch::Contains("share 3 of 3"));
  CHECK_THROWS_WITH(tessera::mesh_summary_parts(mesh, s, nullptr, checked, 0, 1), Catch::Contains("layout"));
  tessera::SceneDesc other = s;
  other.integrator.macrocell = 3;
  const auto s5 =
      tessera::mesh_summary_of_parts(tessera::mesh_summary_parts(mesh, s, layout, checked, 0, 1), mesh, s, layout);
  CHECK_THROWS_WITH(tessera::prepare(mesh, other, layout, checked, s5), Catch::Contains("macrocell edge"));
  CHECK_THROWS_WITH(tessera::prepare(mesh, s, nullptr, checked, s5), Catch::Contains("layout"));
}

TEST_CASE("mesh summary: a share checks the indices it reads unless a receipt covers them", "[mesh][summary][errors]") {
  CutGrid grid(tessera::Association::Vertex);
  const tessera::SceneDesc s = share_scene();
  const auto layout = tessera::prepare(grid.owned.mesh, s).mesh_layout();
  grid.owned.owned[0]->conn64[8 * 3 + 5] = 1 << 30;  // domain 0 (listed first): an index far outside
  CHECK_THROWS_WITH(tessera::mesh_summary_parts(grid.owned.mesh, s, layout, {}, 0, 2),
                    Catch::Contains("vertex index 1073741824"));
}
