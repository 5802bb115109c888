// A mesh's layout (mesh/mesh_layout.h) shared between prepares of the same mesh with other
// values: the image is bit-identical to a prepare that builds it; a layout that does not fit
// the mesh (another cell count, shape or domain count) is not used; the layout's canonical
// order does not depend on the values.
#include <tessera/render.h>

#include <catch2/catch.hpp>
#include <tbb/task_arena.h>

#include "mesh/mesh_layout.h"
#include "test_mesh_support.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <vector>

using tessera::Vec3;
using namespace tessera_mesh_test;
using tessera_test::render_film;

namespace {

tessera::SceneDesc scene() {
  tessera::SceneDesc s;
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = 8.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(tessera::Color(0.6, 0.5, 0.4));
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = tessera::Color(0.8);
  s.lights.push_back(tessera::SphereLightDesc{Vec3(1.6, 1.8, -0.6), 0.3, tessera::Color(20.0)});
  s.camera.position = Vec3(0.5, 0.6, -2.2);
  s.camera.look_at = Vec3(0.5);
  s.camera.fov_deg = 35.0;
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 4;
  s.image = {20, 16, 4, 0.0};
  return s;
}

bool same(const tessera::Film& a, const tessera::Film& b) {
  return a.pixels().size() == b.pixels().size() &&
         std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(tessera::PixelSums)) == 0;
}

ElementList warped(double phase) {
  return grid_hexes(
      6, 5, 4, Vec3(0.0), Vec3(1.0 / 6, 1.0 / 5, 1.0 / 4),
      [&](const Vec3& p) { return 0.5 + 0.5 * std::sin(6.0 * p.x + phase) * std::cos(4.0 * p.y + p.z); },
      [](const Vec3& p) { return Vec3(p.x + 0.08 * p.y * p.y, p.y, p.z + 0.05 * p.x); });
}

}  // namespace

TEST_CASE("mesh layout: reused for other values, the image is bit-identical to a fresh build", "[mesh][reuse]") {
  const ElementList first = warped(0.0), second = warped(1.3);
  for (const bool tets : {false, true}) {
    const OwnedMesh a = cut(tets ? hexes_to_tets(first) : first, std::vector<int>(tets ? 720 : 120, 0), {0});
    const OwnedMesh b = cut(tets ? hexes_to_tets(second) : second, std::vector<int>(tets ? 720 : 120, 0), {0});
    const tessera::PreparedScene pa = tessera::prepare(a.mesh, scene());
    REQUIRE(pa.mesh_layout());
    CHECK_FALSE(pa.mesh_layout_reused());
    // The second step's values on the same geometry (other arrays, same shapes and counts)
    const tessera::PreparedScene reused = tessera::prepare(b.mesh, scene(), pa.mesh_layout());
    CHECK(reused.mesh_layout_reused());
    CHECK(reused.mesh_layout() == pa.mesh_layout());
    const tessera::PreparedScene fresh = tessera::prepare(b.mesh, scene());
    CHECK(same(render_film(reused), render_film(fresh)));
    CHECK_FALSE(same(render_film(reused), render_film(pa)));  // the values did change the image
  }
}

TEST_CASE("mesh layout: one that does not fit the mesh is rebuilt, not used", "[mesh][reuse]") {
  const ElementList m = warped(0.0);
  const OwnedMesh one = one_domain(m);
  const tessera::PreparedScene p = tessera::prepare(one.mesh, scene());
  // Two domains, another cell count, tets: each rebuilds, and renders as without the layout
  std::vector<int> halves(120);
  for (std::size_t e = 0; e < halves.size(); ++e) halves[e] = e < 60 ? 0 : 1;
  const OwnedMesh two = cut(m, halves, {1, 0});
  const OwnedMesh tets = one_domain(hexes_to_tets(m));
  const OwnedMesh smaller =
      one_domain(grid_hexes(5, 5, 4, Vec3(0.0), Vec3(0.2, 0.2, 0.25), [](const Vec3&) { return 0.5; }));
  for (const OwnedMesh* other : {&two, &tets, &smaller}) {
    const tessera::PreparedScene q = tessera::prepare(other->mesh, scene(), p.mesh_layout());
    CHECK_FALSE(q.mesh_layout_reused());
    CHECK(same(render_film(q), render_film(tessera::prepare(other->mesh, scene()))));
  }
  // A fitting mesh whose descriptors are bad is still refused (check_mesh_arrays)
  OwnedMesh bad = one_domain(m);
  bad.mesh.domains[0].field.count -= 1;
  CHECK_THROWS_WITH(tessera::prepare(bad.mesh, scene(), p.mesh_layout()), Catch::Contains("mesh domain 0"));
}

TEST_CASE("mesh layout: a broken promise is refused where the kernels would read outside the arrays", "[mesh][reuse]") {
  const ElementList m = warped(0.0);
  const OwnedMesh first = one_domain(m);
  const tessera::PreparedScene p = tessera::prepare(first.mesh, scene());
  // The same counts and shapes (the layout fits), but an index out of range or a vertex moved
  // to NaN: named as check_mesh names them, though the layout is reused
  const auto conn = [](OwnedMesh& o) { return o.owned[0]->conn32.data(); };  // int32 indices
  OwnedMesh out = one_domain(m);
  conn(out)[8 * 7 + 3] = static_cast<std::int32_t>(m.vertex.size());
  CHECK_THROWS_WITH(tessera::prepare(out.mesh, scene(), p.mesh_layout()),
                    Catch::Contains("mesh domain 0: element 7: vertex index " + std::to_string(m.vertex.size()) +
                                    " (entry 3) is outside"));
  OwnedMesh negative = one_domain(m);
  conn(negative)[0] = -1;
  CHECK_THROWS_WITH(tessera::prepare(negative.mesh, scene(), p.mesh_layout()),
                    Catch::Contains("element 0: vertex index -1 (entry 0)"));
  OwnedMesh nan = one_domain(m);
  nan.owned[0]->y[5] = std::nan("");
  CHECK_THROWS_WITH(tessera::prepare(nan.mesh, scene(), p.mesh_layout()),
                    Catch::Contains("vertex 5 has a non-finite coordinate"));
  // The shapes are the promise's: an element turned inside out is not looked at (check_mesh
  // refuses it), and the render reads inside the arrays
  OwnedMesh inverted = one_domain(m);
  std::int32_t* c = conn(inverted);
  std::swap(c[8 * 10 + 0], c[8 * 10 + 4]);
  std::swap(c[8 * 10 + 1], c[8 * 10 + 5]);
  std::swap(c[8 * 10 + 2], c[8 * 10 + 6]);
  std::swap(c[8 * 10 + 3], c[8 * 10 + 7]);
  CHECK_THROWS_WITH(tessera::check_mesh(inverted.mesh), Catch::Contains("element 10: hex is inverted"));
  const tessera::PreparedScene q = tessera::prepare(inverted.mesh, scene(), p.mesh_layout());
  CHECK(q.mesh_layout_reused());
  CHECK(render_film(q).pixels().size() == 20u * 16u);
}

TEST_CASE("mesh layout: a broken promise that turned a real cell into a ghost is refused", "[mesh][reuse]") {
  // A ghost cell's indices are never checked, so a reused layout must not list one: the
  // promise covers the ghost masks (the geometry hash does), and breaking it is named
  const ElementList m = warped(0.0);
  OwnedMesh first = one_domain(m);
  std::vector<std::uint8_t> mask(m.element.size(), 0);
  tessera::MeshDomain& d0 = first.mesh.domains[0];
  d0.ghosts = {mask.data(), 1, static_cast<std::int64_t>(mask.size())};
  const tessera::PreparedScene p = tessera::prepare(first.mesh, scene());
  mask[9] = 1;  // cell 9 a ghost now, with an index far outside the vertices
  first.owned[0]->conn32[8 * 9 + 2] = 1 << 30;
  CHECK_THROWS_WITH(tessera::prepare(first.mesh, scene(), p.mesh_layout()),
                    Catch::Contains("mesh domain 0: element 9 is a ghost now but was real"));
  // Not reused, the same mesh is sound: cell 9 is left out
  CHECK_NOTHROW(tessera::prepare(first.mesh, scene()));
}

TEST_CASE("mesh receipt: prepare takes a check's receipt for the same arrays instead of checking again",
          "[mesh][reuse][receipt]") {
  const ElementList m = warped(0.0);
  const OwnedMesh a = one_domain(m);
  const tessera::MeshChecked full = tessera::check_mesh(a.mesh);
  const tessera::MeshChecked indices = tessera::check_mesh_indices(a.mesh);
  CHECK(full.covers(a.mesh, true));
  CHECK(full.covers(a.mesh, false));
  CHECK(indices.covers(a.mesh, false));
  CHECK_FALSE(indices.covers(a.mesh, true));  // the shapes were not looked at
  CHECK_FALSE(tessera::MeshChecked{}.covers(a.mesh, false));
  CHECK(full.values() == nullptr);  // a host check measures no values
  // Any descriptor that differs is another mesh: other arrays, a count, a stride, a mask, the
  // memory it is in
  const OwnedMesh b = one_domain(m);  // the same contents in other arrays
  CHECK_FALSE(full.covers(b.mesh, false));
  for (int change = 0; change < 5; ++change) {
    tessera::Mesh other = a.mesh;
    tessera::MeshDomain& d = other.domains[0];
    if (change == 0) d.field.count -= 1;
    if (change == 1) d.coords.byte_stride += 8;
    if (change == 2) d.ghosts = {reinterpret_cast<const std::uint8_t*>(d.field.data), 1, d.ncells};
    if (change == 3) other.device = true;
    if (change == 4) other.domains.push_back(d);
    CHECK_FALSE(full.covers(other, false));
  }

  // Covered: the check is not run again. The proof: an element inverted after the receipt
  // was taken (a promise the caller broke) passes, and is refused without the receipt
  OwnedMesh inverted = one_domain(m);
  const tessera::MeshChecked before = tessera::check_mesh(inverted.mesh);
  std::int32_t* c = inverted.owned[0]->conn32.data();
  for (int k = 0; k < 4; ++k) std::swap(c[8 * 10 + k], c[8 * 10 + 4 + k]);
  CHECK_THROWS_WITH(tessera::prepare(inverted.mesh, scene()), Catch::Contains("element 10: hex is inverted"));
  CHECK_NOTHROW(tessera::prepare(inverted.mesh, scene(), nullptr, before));
  // An indices-only receipt does not stand for the shapes a new layout needs
  const tessera::MeshChecked only_indices = tessera::check_mesh_indices(inverted.mesh);
  CHECK_THROWS_WITH(tessera::prepare(inverted.mesh, scene(), nullptr, only_indices),
                    Catch::Contains("element 10: hex is inverted"));
  // ... and a receipt of other arrays stands for nothing
  CHECK_THROWS_WITH(tessera::prepare(inverted.mesh, scene(), nullptr, full), Catch::Contains("hex is inverted"));

  // With the promise kept, the image is the one of a prepare that checks, bit for bit, with a
  // new layout and with a reused one
  const tessera::PreparedScene checked = tessera::prepare(a.mesh, scene());
  const tessera::PreparedScene taken = tessera::prepare(a.mesh, scene(), nullptr, full);
  CHECK_FALSE(taken.mesh_layout_reused());
  CHECK(same(render_film(taken), render_film(checked)));
  const tessera::PreparedScene reused = tessera::prepare(a.mesh, scene(), checked.mesh_layout(), indices);
  CHECK(reused.mesh_layout_reused());
  CHECK(same(render_film(reused), render_film(checked)));
}

TEST_CASE("mesh receipt: check_mesh_copy checks the indices and takes the caller's word for the shapes",
          "[mesh][reuse][receipt]") {
  const ElementList m = warped(0.0);
  OwnedMesh copy = one_domain(m);
  std::int32_t* c = copy.owned[0]->conn32.data();
  for (int k = 0; k < 4; ++k) std::swap(c[8 * 10 + k], c[8 * 10 + 4 + k]);  // a shape check_mesh refuses
  const tessera::MeshChecked word = tessera::check_mesh_copy(copy.mesh);
  CHECK(word.covers(copy.mesh, true));
  CHECK_NOTHROW(tessera::prepare(copy.mesh, scene(), nullptr, word));
  // The indices and vertices are checked, as check_mesh_indices does
  OwnedMesh out = one_domain(m);
  out.owned[0]->conn32[8 * 7 + 3] = static_cast<std::int32_t>(m.vertex.size());
  CHECK_THROWS_WITH(tessera::check_mesh_copy(out.mesh), Catch::Contains("mesh domain 0: element 7: vertex index"));
  OwnedMesh nan = one_domain(m);
  nan.owned[0]->x[3] = std::nan("");
  CHECK_THROWS_WITH(tessera::check_mesh_copy(nan.mesh), Catch::Contains("vertex 3 has a non-finite coordinate"));
  // A sound copy renders as a checked one, bit for bit
  const OwnedMesh sound = one_domain(m);
  CHECK(same(render_film(tessera::prepare(sound.mesh, scene(), nullptr, tessera::check_mesh_copy(sound.mesh))),
             render_film(tessera::prepare(sound.mesh, scene()))));
}

TEST_CASE("mesh receipt: carried to new values over the same geometry arrays, and to nothing else",
          "[mesh][reuse][receipt]") {
  // What a values-only exchange does (several ranks, the geometry from the kept exchange): the
  // receipt of a mesh carried to the same mesh with other field data, same dtype and count
  const ElementList m = warped(0.0);
  const OwnedMesh a = one_domain(m);
  const tessera::MeshChecked full = tessera::check_mesh(a.mesh);
  const OwnedMesh later = one_domain(warped(1.3));  // other values (and other geometry arrays)
  tessera::Mesh next = a.mesh;
  next.domains[0].field.data = later.mesh.domains[0].field.data;
  CHECK_FALSE(full.covers(next, false));
  const tessera::MeshChecked carried = full.with_new_values(next);
  CHECK(carried.covers(next, true));  // the shapes' word carried too
  CHECK_FALSE(carried.covers(a.mesh, false));
  CHECK(tessera::check_mesh_indices(a.mesh).with_new_values(next).covers(next, false));
  CHECK_FALSE(tessera::check_mesh_indices(a.mesh).with_new_values(next).covers(next, true));
  CHECK_FALSE(tessera::MeshChecked{}.with_new_values(next).covers(next, false));
  // Anything else that differs (geometry arrays, the field's dtype, stride or count, a mask,
  // the memory, the domains) carries nothing
  CHECK_FALSE(full.with_new_values(later.mesh).covers(later.mesh, false));
  for (int change = 0; change < 6; ++change) {
    tessera::Mesh other = next;
    tessera::MeshDomain& d = other.domains[0];
    if (change == 0) d.field.count -= 1;
    if (change == 1) d.field.byte_stride += 8;
    if (change == 2) d.field.dtype = tessera::DType::Float32;
    if (change == 3) d.ghosts = {reinterpret_cast<const std::uint8_t*>(d.field.data), 1, d.ncells};
    if (change == 4) other.device = true;
    if (change == 5) other.domains.push_back(d);
    CHECK_FALSE(full.with_new_values(other).covers(other, false));
  }
  // Taken by prepare as the check's word: the image of a prepare that checks, bit for bit
  CHECK(same(render_film(tessera::prepare(next, scene(), nullptr, carried)),
             render_film(tessera::prepare(next, scene()))));
}

TEST_CASE("mesh prepare over threads: the tables and the image do not depend on the thread count", "[mesh][reuse]") {
  // prepare's check, gather, canonical sort, ranges, totals, location lists and the macrocells'
  // fold run over TBB's threads (in chunks of 2048 to 16384 items: a mesh of several chunks;
  // the lists by slabs from 16384 elements, up to four slabs per thread: both meshes; the
  // fold from 32768 elements: the tets)
  const ElementList m = grid_hexes(
      30, 26, 22, Vec3(0.0), Vec3(1.0 / 30, 1.0 / 26, 1.0 / 22),
      [](const Vec3& p) { return 0.5 + 0.5 * std::sin(9.0 * p.x) * std::cos(5.0 * p.y + 2.0 * p.z); },
      [](const Vec3& p) { return Vec3(p.x + 0.08 * p.y * p.y, p.y, p.z + 0.05 * p.x); });
  for (const bool tets : {false, true}) {
    const OwnedMesh om = one_domain(tets ? hexes_to_tets(m) : m);
    std::optional<tessera::Film> first;
    std::vector<tessera::CellRange> first_ranges;
    std::vector<std::uint64_t> first_starts;
    std::vector<std::uint32_t> first_lists;
    std::vector<double> first_boxes;
    for (const int threads : {1, 2, 5}) {
      std::optional<tessera::PreparedScene> p;
      tbb::task_arena(threads).execute([&] { p.emplace(tessera::prepare(om.mesh, scene())); });
      tessera::Film f = render_film(*p);
      INFO((tets ? "tets, " : "hexes, ") << threads << " threads");
      // The macrocells' ranges (folded over threads from 32768 elements on) bit for bit
      const std::span<const tessera::CellRange> ranges = p->summary()->ranges();
      if (tets) REQUIRE(static_cast<std::size_t>(p->summary()->cell_count()) <= m.element.size() * 6 / 4);
      // The layout: the elements' boxes in canonical order and the location lists (counted and
      // filled over threads, each list then in canonical order), bit for bit
      const tessera::MeshLayout& layout = *p->mesh_layout();
      const tessera::MeshFieldView v = layout.view(nullptr);
      const std::size_t cells = static_cast<std::size_t>(v.loc_n[0] * v.loc_n[1] * v.loc_n[2]);
      const std::vector<std::uint64_t> starts(v.first, v.first + cells + 1);
      const std::vector<std::uint32_t> lists(v.list, v.list + starts.back());
      const std::vector<double> boxes(v.box, v.box + 6 * layout.element_count());
      REQUIRE(layout.element_count() == static_cast<std::size_t>(om.mesh.domains[0].cell_count()));
      REQUIRE(starts.back() >= layout.element_count());
      for (std::size_t c = 0; c < cells; ++c)
        REQUIRE(std::is_sorted(lists.begin() + static_cast<std::ptrdiff_t>(starts[c]),
                               lists.begin() + static_cast<std::ptrdiff_t>(starts[c + 1])));
      // ... and they are what a serial fill over the boxes gives (every element in each location
      // cell its box reaches, in canonical order)
      std::vector<std::vector<std::uint32_t>> expect(cells);
      for (std::size_t e = 0; e < layout.element_count(); ++e) {
        std::int64_t c0[3], c1[3];
        for (int a = 0; a < 3; ++a) {
          const auto cell = [&](double x) {
            return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((x - v.loc_lo[a]) * v.loc_inv[a])), 0,
                                            v.loc_n[a] - 1);
          };
          c0[a] = cell(v.box[6 * e + a]);
          c1[a] = cell(v.box[6 * e + 3 + a]);
        }
        for (std::int64_t k = c0[2]; k <= c1[2]; ++k)
          for (std::int64_t j = c0[1]; j <= c1[1]; ++j)
            for (std::int64_t i = c0[0]; i <= c1[0]; ++i)
              expect[static_cast<std::size_t>((k * v.loc_n[1] + j) * v.loc_n[0] + i)].push_back(
                  static_cast<std::uint32_t>(e));
      }
      std::size_t wrong = 0;
      for (std::size_t c = 0; c < cells; ++c)
        wrong +=
            !std::equal(lists.begin() + static_cast<std::ptrdiff_t>(starts[c]),
                        lists.begin() + static_cast<std::ptrdiff_t>(starts[c + 1]), expect[c].begin(), expect[c].end());
      CHECK(wrong == 0);
      if (first) {
        const bool same_starts = starts == first_starts, same_lists = lists == first_lists;
        CHECK(same_starts);
        CHECK(same_lists);
        CHECK(std::memcmp(boxes.data(), first_boxes.data(), boxes.size() * sizeof(double)) == 0);
        CHECK(same(f, *first));
        REQUIRE(ranges.size() == first_ranges.size());
        std::size_t differ = 0;
        for (std::size_t c = 0; c < ranges.size(); ++c) {
          const tessera::CellRange &a = ranges[c], &b = first_ranges[c];
          differ += std::memcmp(&a.lo, &b.lo, sizeof a.lo) != 0 || std::memcmp(&a.hi, &b.hi, sizeof a.hi) != 0 ||
                    a.nan != b.nan || a.pos_inf != b.pos_inf || a.neg_inf != b.neg_inf;
        }
        CHECK(differ == 0);
      } else {
        first.emplace(std::move(f));
        first_ranges.assign(ranges.begin(), ranges.end());
        first_starts = starts;
        first_lists = lists;
        first_boxes = boxes;
      }
    }
  }
}

TEST_CASE("mesh geometry hash: the geometry, not the values nor where the arrays are, under any thread count",
          "[mesh][reuse][hash]") {
  const ElementList m = grid_hexes(
      24, 20, 18, Vec3(0.0), Vec3(1.0 / 24, 1.0 / 20, 1.0 / 18), [](const Vec3& p) { return p.x * p.y; },
      [](const Vec3& p) { return Vec3(p.x + 0.05 * p.y * p.y, p.y, p.z); });
  const OwnedMesh a = one_domain(m);
  const tessera::MeshGeometryHash h = tessera::mesh_geometry_hash(a.mesh);
  // The same geometry in other arrays, with other values: the same hash
  OwnedMesh b = one_domain(m);
  for (double& v : b.owned[0]->values) v = 7.0 - v;
  CHECK(tessera::mesh_geometry_hash(b.mesh) == h);
  for (const int threads : {1, 3}) {
    tessera::MeshGeometryHash t;
    tbb::task_arena(threads).execute([&] { t = tessera::mesh_geometry_hash(a.mesh); });
    CHECK(t == h);
  }
  // Any change of the geometry changes both values: a coordinate by one ulp, an index, a
  // ghost flag, the dims of another cut
  const auto both_differ = [&](const tessera::Mesh& other) {
    const tessera::MeshGeometryHash o = tessera::mesh_geometry_hash(other);
    return o.a != h.a && o.b != h.b;
  };
  OwnedMesh moved = one_domain(m);
  moved.owned[0]->z[100] = std::nextafter(moved.owned[0]->z[100], 2.0);
  CHECK(both_differ(moved.mesh));
  OwnedMesh swapped = one_domain(m);
  std::swap(swapped.owned[0]->conn32[8 * 3000 + 1], swapped.owned[0]->conn32[8 * 3000 + 2]);
  CHECK(both_differ(swapped.mesh));
  OwnedMesh ghosted = one_domain(m);
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(ghosted.mesh.domains[0].ncells), 0);
  ghosted.mesh.domains[0].ghosts = {mask.data(), 1, static_cast<std::int64_t>(mask.size())};
  const tessera::MeshGeometryHash no_ghost = tessera::mesh_geometry_hash(ghosted.mesh);
  CHECK(no_ghost != h);  // a mask of zeros is still a mask
  mask[5000] = 1;
  const tessera::MeshGeometryHash one_ghost = tessera::mesh_geometry_hash(ghosted.mesh);
  CHECK(one_ghost.a != no_ghost.a);
  CHECK(one_ghost.b != no_ghost.b);
  std::vector<int> halves(m.element.size());
  for (std::size_t e = 0; e < halves.size(); ++e) halves[e] = e < halves.size() / 2 ? 0 : 1;
  CHECK(both_differ(cut(m, halves, {0, 1}).mesh));
  // Unreadable or bad descriptors: named as check_mesh_arrays names them
  OwnedMesh bad = one_domain(m);
  bad.mesh.domains[0].field.count -= 1;
  CHECK_THROWS_WITH(tessera::mesh_geometry_hash(bad.mesh), Catch::Contains("mesh domain 0"));
}
