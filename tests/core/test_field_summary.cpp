// Tests for FieldSummary and prepare()'s reuse of it: every cell range equals a brute-force
// scan of the cell's vertex block (bitwise, zeros recorded as +0.0, for any thread count),
// partial summaries of blocks combine to the whole field's bit for bit, and a reused summary gives the bit-identical image while a mismatching one is rebuilt.
#include <tessera/field_summary.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "field/summary_accumulate.h"
#include "sampling/rng.h"
#include "test_support.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using tessera::CellRange;
using tessera::DType;
using tessera::FieldSummary;
using tessera::FieldView;

namespace {

/// Bit equality (distinguishes -0.0 from +0.0).
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Values drawn from a small set so that ties (+0.0 and -0.0 among them) are common, plus
/// NaN and +-Inf when T has them.
template <class T>
std::vector<T> random_values(tessera::Rng& rng, std::int64_t count) {
  std::vector<T> v(static_cast<std::size_t>(count));
  for (T& x : v) {
    const double r = rng.uniform();
    if constexpr (std::is_floating_point_v<T>) {
      if (r < 0.04) x = std::numeric_limits<T>::quiet_NaN();
      else if (r < 0.06) x = std::numeric_limits<T>::infinity();
      else if (r < 0.08) x = -std::numeric_limits<T>::infinity();
      else if (r < 0.25) x = T(-0.0);
      else if (r < 0.40) x = T(0.0);
      else x = static_cast<T>(std::floor(rng.uniform() * 9.0) - 4.0) * T(0.5);
    } else {
      x = static_cast<T>(std::floor(rng.uniform() * 200.0) - (std::is_signed_v<T> ? 100.0 : 0.0));
    }
  }
  return v;
}

/// The summary's definition, one vertex at a time: cell c along an axis covers vertices
/// c*E ..= min((c+1)*E, n-1); values folded in (k, j, i) order with std::min / std::max,
/// every zero taken as +0.0.
struct BruteForce {
  std::int64_t nc[3];
  std::vector<CellRange> cells;
  std::uint64_t nans = 0;
  double lo, hi;
};

BruteForce brute_force(const FieldView& f, int edge) {
  const double inf = std::numeric_limits<double>::infinity();
  BruteForce b;
  for (int a = 0; a < 3; ++a) b.nc[a] = std::max<std::int64_t>(1, (f.dims[a] - 1 + edge - 1) / edge);
  b.lo = inf;
  b.hi = -inf;
  tessera::dispatch_dtype(f, [&](auto view) {
    for (std::int64_t k = 0; k < f.dims[2]; ++k)
      for (std::int64_t j = 0; j < f.dims[1]; ++j)
        for (std::int64_t i = 0; i < f.dims[0]; ++i) {
          const double v = view.load(i, j, k) == 0.0 ? 0.0 : view.load(i, j, k);
          if (std::isnan(v)) ++b.nans;
          if (std::isfinite(v)) b.lo = std::min(b.lo, v), b.hi = std::max(b.hi, v);
        }
    for (std::int64_t cz = 0; cz < b.nc[2]; ++cz)
      for (std::int64_t cy = 0; cy < b.nc[1]; ++cy)
        for (std::int64_t cx = 0; cx < b.nc[0]; ++cx) {
          CellRange r{inf, -inf, false, false, false};
          for (std::int64_t k = cz * edge; k <= std::min((cz + 1) * edge, f.dims[2] - 1); ++k)
            for (std::int64_t j = cy * edge; j <= std::min((cy + 1) * edge, f.dims[1] - 1); ++j)
              for (std::int64_t i = cx * edge; i <= std::min((cx + 1) * edge, f.dims[0] - 1); ++i) {
                const double v = view.load(i, j, k) == 0.0 ? 0.0 : view.load(i, j, k);
                if (std::isnan(v)) r.nan = true;
                else if (v == inf) r.pos_inf = true;
                else if (v == -inf) r.neg_inf = true;
                else r.lo = std::min(r.lo, v), r.hi = std::max(r.hi, v);
              }
          b.cells.push_back(r);
        }
  });
  return b;
}

/// Number of cells (and totals) where the summary differs from the brute force, bitwise.
int mismatches(const FieldSummary& s, const BruteForce& b) {
  int bad = 0;
  for (int a = 0; a < 3; ++a) bad += s.cells()[a] != b.nc[a];
  if (bad) return bad;
  for (std::size_t c = 0; c < b.cells.size(); ++c) {
    const CellRange &x = s.ranges()[c], &y = b.cells[c];
    bad += !same_bits(x.lo, y.lo) || !same_bits(x.hi, y.hi) || x.nan != y.nan || x.pos_inf != y.pos_inf ||
           x.neg_inf != y.neg_inf;
  }
  bad += s.nan_vertices() != b.nans;
  const bool finite = b.lo <= b.hi;
  bad += s.has_finite() != finite;
  bad += !same_bits(s.value_min(), finite ? b.lo : 0.0) || !same_bits(s.value_max(), finite ? b.hi : 0.0);
  return bad;
}

template <class T>
void check_against_brute_force(std::uint64_t seed) {
  tessera::Rng rng(seed, 0, 0, 0);
  const std::int64_t shapes[][3] = {{1, 1, 1}, {1, 7, 5}, {13, 9, 11}, {17, 2, 33}, {9, 9, 9}, {40, 3, 6}};
  for (const auto& n : shapes) {
    const std::vector<T> data = random_values<T>(rng, n[0] * n[1] * n[2]);
    const DType dt = tessera_test::dtype_of<T>();
    // C order, and the same bytes seen mirrored along j (negative stride) and transposed
    const FieldView c_order = FieldView::contiguous(data.data(), dt, n[0], n[1], n[2]);
    FieldView mirrored = c_order;
    mirrored.data = reinterpret_cast<const unsigned char*>(data.data()) + (n[1] - 1) * c_order.byte_strides[1];
    mirrored.byte_strides[1] = -c_order.byte_strides[1];
    FieldView transposed = c_order;
    std::swap(transposed.dims[0], transposed.dims[2]);
    std::swap(transposed.byte_strides[0], transposed.byte_strides[2]);
    const std::int64_t max_dim = std::max({n[0], n[1], n[2]});
    for (const FieldView& view : {c_order, mirrored, transposed})
      for (const int edge : {1, 3, 8, static_cast<int>(max_dim), 1 << 30}) {
        const FieldSummary s(view, edge);
        INFO("dtype " << tessera::dtype_name(dt) << " dims " << view.dims[0] << "x" << view.dims[1] << "x"
                      << view.dims[2] << " strides " << view.byte_strides[0] << "," << view.byte_strides[1] << ","
                      << view.byte_strides[2] << " edge " << edge);
        REQUIRE(mismatches(s, brute_force(view, edge)) == 0);
      }
  }
}

std::vector<float> blob(int n, float nan_every = 0) {
  std::vector<float> v = tessera_test::blobby_field(n, n, n);
  if (nan_every > 0)
    for (std::size_t i = 0; i < v.size(); i += static_cast<std::size_t>(nan_every))
      v[i] = std::numeric_limits<float>::quiet_NaN();
  return v;
}

tessera::SceneDesc small_scene(int n) {
  tessera::SceneDesc s;
  s.geometry.spacing = tessera::Vec3(1.0 / (n - 1));
  s.tf.density_scale = 20.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.2, 1.0}, {0.0, 0.5, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(tessera::Color(0.8, 0.7, 0.6));
  s.camera.position = tessera::Vec3(0.5, 0.5, -2.0);
  s.camera.look_at = tessera::Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 35.0;
  s.lights.push_back(tessera::SphereLightDesc{tessera::Vec3(2.0, 0.5, 0.0), 0.3, tessera::Color(5.0)});
  s.image = {16, 16, 4, 0.0};
  s.integrator.macrocell = 4;
  s.options.seed = 9;
  return s;
}

bool same_film(const tessera::Film& a, const tessera::Film& b) {
  return a.pixels().size() == b.pixels().size() &&
         std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(a.pixels()[0])) == 0;
}

/// The parts of the blocks of `f` cut at the given planes along each axis (each list starts
/// with 0 and ends with dims), combined as the MPI reductions would, in reverse block order.
/// `merged`: instead, every block accumulated into one set of parts (FieldSummary::accumulate),
/// in reverse block order.
std::shared_ptr<const FieldSummary> from_blocks(const FieldView& f, int edge, const std::vector<std::int64_t> cuts[3],
                                                bool merged = false) {
  std::vector<FieldSummary::Parts> parts;
  std::vector<std::pair<FieldView, std::array<std::int64_t, 3>>> blocks;
  for (std::size_t z = 0; z + 1 < cuts[2].size(); ++z)
    for (std::size_t y = 0; y + 1 < cuts[1].size(); ++y)
      for (std::size_t x = 0; x + 1 < cuts[0].size(); ++x) {
        const std::int64_t off[3] = {cuts[0][x], cuts[1][y], cuts[2][z]};
        FieldView b = f;
        b.data = static_cast<const unsigned char*>(f.data) + off[0] * f.byte_strides[0] + off[1] * f.byte_strides[1] +
                 off[2] * f.byte_strides[2];
        b.dims[0] = cuts[0][x + 1] - off[0];
        b.dims[1] = cuts[1][y + 1] - off[1];
        b.dims[2] = cuts[2][z + 1] - off[2];
        if (merged) blocks.push_back({b, {off[0], off[1], off[2]}});
        else parts.push_back(FieldSummary::partial(b, off, f.dims, edge));
      }
  if (merged) {
    const std::int64_t zero[3] = {0, 0, 0};
    FieldSummary::Parts all = FieldSummary::partial(FieldView{}, zero, f.dims, edge);
    for (std::size_t n = blocks.size(); n-- > 0;)
      FieldSummary::accumulate(all, blocks[n].first, blocks[n].second.data(), f.dims, edge);
    return FieldSummary::from_parts(std::move(all), tessera::FieldLayout::of(f), edge);
  }
  FieldSummary::Parts all = parts.back();
  for (std::size_t p = parts.size() - 1; p-- > 0;) {
    const FieldSummary::Parts& q = parts[p];
    for (std::size_t c = 0; c < all.lo.size(); ++c) {
      all.lo[c] = std::min(all.lo[c], q.lo[c]);
      all.hi[c] = std::max(all.hi[c], q.hi[c]);
      all.flags[c] |= q.flags[c];
    }
    all.nan += q.nan;
    all.vmin = std::min(all.vmin, q.vmin);
    all.vmax = std::max(all.vmax, q.vmax);
  }
  return FieldSummary::from_parts(std::move(all), tessera::FieldLayout::of(f), edge);
}

template <class T>
void check_parts(std::uint64_t seed) {
  tessera::Rng rng(seed, 0, 0, 0);
  const std::int64_t n[3] = {13, 9, 11};
  const std::vector<T> data = random_values<T>(rng, n[0] * n[1] * n[2]);
  const DType dt = tessera_test::dtype_of<T>();
  const FieldView f = FieldView::contiguous(data.data(), dt, n[0], n[1], n[2]);
  // 1..4 blocks per axis, uneven, with 1-vertex-thick blocks and cuts on and off cell edges
  const std::vector<std::vector<std::int64_t>> splits_x = {{0, 13}, {0, 6, 13}, {0, 1, 2, 13}, {0, 3, 4, 12, 13}};
  const std::vector<std::vector<std::int64_t>> splits_y = {{0, 9}, {0, 4, 9}, {0, 8, 9}};
  const std::vector<std::vector<std::int64_t>> splits_z = {{0, 11}, {0, 5, 6, 11}, {0, 2, 7, 10, 11}};
  for (const int edge : {1, 3, 4, 8, 1 << 30})
    for (const auto& sx : splits_x)
      for (const auto& sy : splits_y)
        for (const auto& sz : splits_z) {
          const std::vector<std::int64_t> cuts[3] = {sx, sy, sz};
          for (const bool merged : {false, true}) {
            const auto combined = from_blocks(f, edge, cuts, merged);
            const FieldSummary whole(f, edge);
            INFO((merged ? "accumulated, " : "")
                 << "dtype " << tessera::dtype_name(dt) << " edge " << edge << " blocks " << sx.size() - 1 << "x"
                 << sy.size() - 1 << "x" << sz.size() - 1);
            REQUIRE(combined->cell_count() == whole.cell_count());
            int bad = 0;
            for (std::size_t c = 0; c < whole.ranges().size(); ++c) {
              const CellRange &x = combined->ranges()[c], &y = whole.ranges()[c];
              bad += !same_bits(x.lo, y.lo) || !same_bits(x.hi, y.hi) || x.nan != y.nan || x.pos_inf != y.pos_inf ||
                     x.neg_inf != y.neg_inf;
            }
            REQUIRE(bad == 0);
            REQUIRE(combined->nan_vertices() == whole.nan_vertices());
            REQUIRE(same_bits(combined->value_min(), whole.value_min()));
            REQUIRE(same_bits(combined->value_max(), whole.value_max()));
            REQUIRE(combined->has_finite() == whole.has_finite());
            REQUIRE(combined->matches(f, edge));
          }
        }
}

}  // namespace

TEST_CASE("FieldSummary: partials of blocks that tile the field combine to the whole's, bit for bit",
          "[field_summary]") {
  check_parts<float>(201);
  check_parts<double>(202);
  check_parts<std::uint8_t>(203);
  check_parts<std::int16_t>(204);
  check_parts<std::uint16_t>(205);
}

TEST_CASE("FieldSummary: a block's partial leaves the cells it does not touch empty", "[field_summary]") {
  const std::vector<float> data(4 * 4 * 4, 2.0f);
  const FieldView b = FieldView::contiguous(data.data(), DType::Float32, 4, 4, 4);
  const std::int64_t off[3] = {0, 0, 0}, dims[3] = {16, 4, 4};
  const FieldSummary::Parts p = FieldSummary::partial(b, off, dims, 4);
  REQUIRE(p.cells[0] == 4);
  CHECK(p.lo[0] == 2.0);
  CHECK(p.lo[1] == INFINITY);  // vertex 4 (cell 1's first) is outside the block
  CHECK(p.hi[3] == -INFINITY);
  CHECK(p.nan == 0);
  const std::int64_t outside[3] = {13, 0, 0};
  CHECK_THROWS_WITH(FieldSummary::partial(b, outside, dims, 4), Catch::Contains("not inside the field"));
  FieldSummary::Parts bad = p;
  bad.lo.pop_back();
  CHECK_THROWS_WITH(FieldSummary::from_parts(std::move(bad), {}, 4), Catch::Contains("for 4 cells"));
}

TEST_CASE("FieldSummary: every cell range equals a brute-force scan of its vertex block", "[field_summary]") {
  check_against_brute_force<float>(101);
  check_against_brute_force<double>(102);
  check_against_brute_force<std::uint8_t>(103);
  check_against_brute_force<std::int16_t>(104);
  check_against_brute_force<std::uint16_t>(105);
}

TEST_CASE("FieldSummary: bit-identical for any thread count, layout and edge recorded", "[field_summary]") {
  tessera::Rng rng(7, 0, 0, 0);
  const std::vector<float> data = random_values<float>(rng, 37 * 29 * 70);
  const FieldView view = FieldView::contiguous(data.data(), DType::Float32, 37, 29, 70);
  for (const int edge : {2, 5, 70}) {
    std::shared_ptr<const FieldSummary> one, many;
    {
      tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
      one = FieldSummary::build(view, edge);
    }
    many = FieldSummary::build(view, edge);
    REQUIRE(one->cell_count() == many->cell_count());
    CHECK(std::memcmp(one->ranges().data(), many->ranges().data(), one->ranges().size() * sizeof(CellRange)) == 0);
    CHECK(one->nan_vertices() == many->nan_vertices());
    CHECK(same_bits(one->value_min(), many->value_min()));
    CHECK(mismatches(*many, brute_force(view, edge)) == 0);
    CHECK(many->matches(view, edge));
    CHECK_FALSE(many->matches(view, edge + 1));
  }
  CHECK_THROWS_WITH(FieldSummary(view, 0), Catch::Contains("macrocell edge must be >= 1"));
}

TEST_CASE("FieldSummary: a field without finite values", "[field_summary]") {
  const std::vector<float> data(27, std::numeric_limits<float>::quiet_NaN());
  const FieldSummary s(FieldView::contiguous(data.data(), DType::Float32, 3, 3, 3), 2);
  CHECK_FALSE(s.has_finite());
  CHECK(s.value_min() == 0.0);
  CHECK(s.value_max() == 0.0);
  CHECK(s.nan_vertices() == 27u);
  // field_range() says "none" distinctly from an all-zero field
  CHECK_FALSE(tessera::field_range(FieldView::contiguous(data.data(), DType::Float32, 3, 3, 3)));
  const std::vector<float> zeros(27, 0.0f);
  const auto r = tessera::field_range(FieldView::contiguous(zeros.data(), DType::Float32, 3, 3, 3));
  REQUIRE(r);
  CHECK(r->first == 0.0);
  CHECK(r->second == 0.0);
}

TEST_CASE("prepare with a reused summary: no new summary, bit-identical image", "[field_summary][render]") {
  constexpr int n = 16;
  const std::vector<float> data = blob(n, 13);
  const FieldView view = FieldView::contiguous(data.data(), DType::Float32, n, n, n);
  for (const tessera::MajorantMode mode : {tessera::MajorantMode::Grid, tessera::MajorantMode::Global}) {
    tessera::SceneDesc scene = small_scene(n);
    scene.integrator.majorant = mode;
    const tessera::PreparedScene fresh = tessera::prepare(view, scene);
    CHECK_FALSE(fresh.summary_reused());
    REQUIRE(fresh.summary());
    CHECK(fresh.summary()->edge() == tessera::majorant_edge(view, scene.integrator));
    if (mode == tessera::MajorantMode::Global) CHECK(fresh.summary()->cell_count() == 1);

    // Another camera and transfer function over the same field: the same summary object
    tessera::SceneDesc other = scene;
    other.camera.position = tessera::Vec3(-1.5, 0.5, 0.5);
    other.tf.density_scale = 35.0;
    const tessera::PreparedScene reused = tessera::prepare(view, other, fresh.summary());
    CHECK(reused.summary_reused());
    CHECK(reused.summary() == fresh.summary());
    const tessera::PreparedScene rebuilt = tessera::prepare(view, other);
    tessera::RenderStats st_reused, st_rebuilt;
    const tessera::Film a = tessera_test::render_film(reused, &st_reused);
    const tessera::Film b = tessera_test::render_film(rebuilt, &st_rebuilt);
    CHECK(same_film(a, b));
    CHECK(st_reused.samples > 0);
    CHECK(st_reused.nan_voxels_seen == st_rebuilt.nan_voxels_seen);
    CHECK(st_reused.nan_voxels_seen > 0);
    CHECK(st_reused.null_collisions == st_rebuilt.null_collisions);
  }
}

TEST_CASE("prepare rebuilds a summary of another edge or layout", "[field_summary][render]") {
  constexpr int n = 12;
  const std::vector<float> data = blob(n);
  const FieldView view = FieldView::contiguous(data.data(), DType::Float32, n, n, n);
  const tessera::SceneDesc scene = small_scene(n);  // macrocell 4
  const auto edge2 = FieldSummary::build(view, 2);

  SECTION("another macrocell edge") {
    const tessera::PreparedScene p = tessera::prepare(view, scene, edge2);
    CHECK_FALSE(p.summary_reused());
    CHECK(p.summary()->edge() == 4);
  }
  SECTION("the global majorant needs one cell") {
    tessera::SceneDesc global = scene;
    global.integrator.majorant = tessera::MajorantMode::Global;
    const tessera::PreparedScene p = tessera::prepare(view, global, FieldSummary::build(view, 4));
    CHECK_FALSE(p.summary_reused());
    CHECK(p.summary()->cell_count() == 1);
  }
  SECTION("the same values at another address: rebuilt, though they would match") {
    const std::vector<float> copy = data;
    const FieldView moved = FieldView::contiguous(copy.data(), DType::Float32, n, n, n);
    const tessera::PreparedScene p = tessera::prepare(moved, scene, FieldSummary::build(view, 4));
    CHECK_FALSE(p.summary_reused());
    CHECK(p.summary()->layout() == tessera::FieldLayout::of(moved));
  }
  SECTION("another field at the same address: other dims, strides or dtype") {
    // A summary of the whole field must not serve a sub-box or a reinterpretation of it,
    // whose values differ: the image must equal the one from a fresh prepare
    const auto whole = FieldSummary::build(view, 4);
    FieldView sub = view;
    sub.dims[0] = n / 2;
    FieldView strided = view;
    strided.dims[0] = n / 2;
    strided.byte_strides[0] = 8;
    const FieldView as_int16 = FieldView::contiguous(data.data(), DType::Int16, 2 * n, n, n);
    for (const FieldView& other : {sub, strided, as_int16}) {
      tessera::SceneDesc s = scene;
      s.geometry.spacing = tessera::Vec3(1.0 / (n - 1));
      if (other.dtype == DType::Int16) s.tf.hi = 40000.0, s.tf.lo = -40000.0;
      const tessera::PreparedScene p = tessera::prepare(other, s, whole);
      CHECK_FALSE(p.summary_reused());
      CHECK(same_film(tessera_test::render_film(p), tessera_test::render_film(tessera::prepare(other, s))));
    }
  }
  SECTION("null: a fresh summary, as prepare(field, scene)") {
    const tessera::PreparedScene p = tessera::prepare(view, scene, nullptr);
    CHECK_FALSE(p.summary_reused());
    CHECK(p.summary()->matches(view, 4));
  }
}

TEST_CASE("a block's window of macrocells is exactly the cells its vertices are folded into", "[summary]") {
  // cell_window is what the device summary of a block at an offset reduces over (only that
  // window comes back): for every axis length, edge, offset and block length it must hold
  // every cell vertex_cells folds a vertex of the block into, and no other
  using tessera::summary_detail::cell_window;
  using tessera::summary_detail::cells_along;
  using tessera::summary_detail::vertex_cells;
  int checked = 0;
  for (std::int64_t global = 1; global <= 21; ++global)
    for (int edge = 1; edge <= 7; ++edge) {
      const std::int64_t cells = cells_along(global, edge);
      for (std::int64_t offset = 0; offset < global; ++offset)
        for (std::int64_t dims = 1; offset + dims <= global; ++dims) {
          std::int64_t lo = cells, hi = -1;
          for (std::int64_t g = offset; g < offset + dims; ++g) {
            std::int64_t own = 0, prev = 0;
            vertex_cells(g, cells, edge, own, prev);
            REQUIRE(own >= 0);
            REQUIRE(own < cells);
            REQUIRE(prev >= 0);
            REQUIRE(prev <= own);
            lo = std::min({lo, own, prev});
            hi = std::max({hi, own, prev});
          }
          std::int64_t first = -1, last = -1;
          cell_window(offset, dims, global, edge, first, last);
          INFO("global " << global << ", edge " << edge << ", offset " << offset << ", dims " << dims);
          REQUIRE(first == lo);
          REQUIRE(last == hi);
          ++checked;
        }
    }
  CHECK(checked > 10000);
}
