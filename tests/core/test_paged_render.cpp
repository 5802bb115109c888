// Distributed mode, core side (brick_cache.h): a scene rendered through a demand-paged field
// (own block in place, the rest fetched brick by brick by a service thread into a bounded
// cache) gives the plain render's pixel sums and counters bit for bit, whatever the block,
// the brick size, the cache capacity (1 slot: a flush at nearly every miss) and the threads;
// several own blocks are read in place (BrickCache::set_in_place), never fetched.
#include <tessera/brick_cache.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "fake_brick_service.h"
#include "test_support.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using tessera::Color;
using tessera::DType;
using tessera::FieldView;
using tessera::Vec3;

namespace {

constexpr std::int64_t NX = 20, NY = 18, NZ = 16;

/// A smooth blob in [0, 1] with a few non-finite and signed-zero vertices (float dtypes) and
/// the dtype's value range otherwise (integers: scaled so the TF range [0, 1] covers them).
std::vector<unsigned char> make_field(DType dt) {
  const std::size_t es = tessera::dtype_size(dt);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(NX * NY * NZ) * es);
  const double scale = dt == DType::UInt8 ? 255.0 : dt == DType::Int16 ? 3000.0 : dt == DType::UInt16 ? 60000.0 : 1.0;
  for (std::int64_t k = 0; k < NZ; ++k)
    for (std::int64_t j = 0; j < NY; ++j)
      for (std::int64_t i = 0; i < NX; ++i) {
        const double x = (i - 9.5) / 8.0, y = (j - 8.5) / 7.0, z = (k - 7.5) / 6.0;
        double v = std::exp(-1.5 * (x * x + y * y + z * z)) * (0.8 + 0.2 * std::sin(1.3 * i + 0.7 * j - 0.4 * k));
        const std::size_t n = static_cast<std::size_t>((k * NY + j) * NX + i);
        unsigned char* p = bytes.data() + n * es;
        switch (dt) {
          case DType::UInt8: {
            const auto t = static_cast<std::uint8_t>(v * scale);
            std::memcpy(p, &t, es);
            break;
          }
          case DType::Int16: {
            const auto t = static_cast<std::int16_t>(v * scale - 200.0);
            std::memcpy(p, &t, es);
            break;
          }
          case DType::UInt16: {
            const auto t = static_cast<std::uint16_t>(v * scale);
            std::memcpy(p, &t, es);
            break;
          }
          default: {
            if (n % 97 == 5) v = std::numeric_limits<double>::quiet_NaN();
            else if (n % 89 == 7) v = std::numeric_limits<double>::infinity();
            else if (n % 83 == 9) v = -std::numeric_limits<double>::infinity();
            else if (n % 13 == 0) v = -0.0;
            if (dt == DType::Float32) {
              const auto t = static_cast<float>(v);
              std::memcpy(p, &t, es);
            } else std::memcpy(p, &v, es);
          }
        }
      }
  return bytes;
}

struct Variant {
  tessera::Scattering scattering = tessera::Scattering::Multiple;
  tessera::ShadowMode shadow = tessera::ShadowMode::Ratio;
  tessera::FreePath free_path = tessera::FreePath::Delta;
  bool emission = true;
  double target_error = 0.0;
  tessera::MajorantMode majorant = tessera::MajorantMode::Grid;
};

tessera::SceneDesc scene_for(DType dt, const Variant& v) {
  tessera::SceneDesc s;
  s.geometry.origin = Vec3(-1.0, -0.9, -0.8);
  s.geometry.spacing = Vec3(0.1);
  const double scale = dt == DType::UInt8 ? 255.0 : dt == DType::Int16 ? 3000.0 : dt == DType::UInt16 ? 60000.0 : 1.0;
  s.tf.lo = dt == DType::Int16 ? -200.0 : 0.0;
  s.tf.hi = s.tf.lo + scale;
  s.tf.density_scale = 15.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.15, 0.5, 1.0}, {0.0, 0.3, 0.8, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.9, 0.6, 0.3), Color(0.3, 0.7, 0.95)});
  s.tf.specular = tessera::ColorTF::constant(Color(0.04));
  if (v.emission) s.tf.emission = tessera::ColorTF({0.0, 0.6, 1.0}, {Color(0.0), Color(0.0), Color(2.0, 0.5, 0.1)});
  s.camera.position = Vec3(1.5, 1.0, -3.0);
  s.camera.look_at = Vec3(0.0, 0.0, 0.0);
  s.camera.fov_deg = 40.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.0, 2.0, 0.0), Vec3(0.0, 0.0, 0.0), 1.5, 1.0, Color(5.0, 4.0, 3.0)});
  s.lights.push_back(tessera::SphereLightDesc{Vec3(-2.0, 0.5, -1.0), 0.4, Color(3.0, 3.0, 6.0)});
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(0.2, 0.25, 0.3);
  s.integrator.scattering = v.scattering;
  s.integrator.shadow = v.shadow;
  s.integrator.free_path = v.free_path;
  s.integrator.max_bounces = 6;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.majorant = v.majorant;
  s.integrator.macrocell = 4;
  s.image = {24, 16, 2, v.target_error};
  s.options.seed = 77;
  s.options.frame = 1;
  s.options.tile = 8;
  return s;
}

struct Result {
  std::vector<tessera::PixelSums> px;
  tessera::RenderStats stats;
};

Result render_plain(const FieldView& whole, const tessera::SceneDesc& s) {
  const tessera::PreparedScene ps = tessera::prepare(whole, s);
  Result r;
  r.px = tessera_test::render_film(ps, &r.stats).pixels();
  return r;
}

/// The whole field's summary as ranks would combine it: partials of two blocks split at k.
std::shared_ptr<const tessera::FieldSummary> combined_summary(const FieldView& whole, int edge) {
  const std::int64_t dims[3] = {NX, NY, NZ};
  const std::int64_t split = NZ / 3;
  FieldView a = whole, b = whole;
  a.dims[2] = split;
  b.dims[2] = NZ - split;
  b.data = static_cast<const unsigned char*>(whole.data) + split * whole.byte_strides[2];
  const std::int64_t oa[3] = {0, 0, 0}, ob[3] = {0, 0, split};
  auto pa = tessera::FieldSummary::partial(a, oa, dims, edge);
  const auto pb = tessera::FieldSummary::partial(b, ob, dims, edge);
  for (std::size_t c = 0; c < pa.lo.size(); ++c) {
    pa.lo[c] = std::min(pa.lo[c], pb.lo[c]);
    pa.hi[c] = std::max(pa.hi[c], pb.hi[c]);
    pa.flags[c] |= pb.flags[c];
  }
  pa.nan += pb.nan;
  pa.vmin = std::min(pa.vmin, pb.vmin);
  pa.vmax = std::max(pa.vmax, pb.vmax);
  return tessera::FieldSummary::from_parts(std::move(pa), tessera::FieldLayout{}, edge);
}

struct Paging {
  int shift = 2;
  std::size_t capacity = 4;
  std::int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  ///< own block (empty when lo == hi)
  int threads = 2;
};

Result render_paged(const FieldView& whole, tessera::SceneDesc s, const Paging& pg,
                    tessera::BrickCacheStats* cache_stats = nullptr) {
  s.options.threads = pg.threads;
  const std::int64_t dims[3] = {NX, NY, NZ};
  tessera::BrickCache cache(tessera::BrickGrid::make(dims, whole.dtype, pg.shift), pg.capacity);
  tessera::PagedField f;
  f.dtype = whole.dtype;
  for (int a = 0; a < 3; ++a) f.dims[a] = dims[a];
  if (pg.hi[0] > pg.lo[0]) {
    f.local = whole;
    f.local.data = static_cast<const unsigned char*>(whole.data) + pg.lo[0] * whole.byte_strides[0] +
                   pg.lo[1] * whole.byte_strides[1] + pg.lo[2] * whole.byte_strides[2];
    for (int a = 0; a < 3; ++a) {
      f.local.dims[a] = pg.hi[a] - pg.lo[a];
      f.offset[a] = pg.lo[a];
    }
  }
  f.cache = &cache;
  const FieldView global = whole;
  const int edge = tessera::majorant_edge(global, s.integrator);
  Result r;
  {
    tessera_test::FakeBrickService service(cache, whole);
    const tessera::PreparedScene ps = tessera::prepare(f, s, combined_summary(whole, edge));
    r.px = tessera_test::render_film(ps, &r.stats).pixels();
  }
  REQUIRE_FALSE(cache.failed());
  if (cache_stats) *cache_stats = cache.stats();
  return r;
}

void require_same(const Result& a, const Result& b) {
  REQUIRE(a.px.size() == b.px.size());
  CHECK(std::memcmp(a.px.data(), b.px.data(), a.px.size() * sizeof(tessera::PixelSums)) == 0);
  CHECK(a.stats.samples == b.stats.samples);
  CHECK(a.stats.discarded_samples == b.stats.discarded_samples);
  CHECK(a.stats.free_flight_lookups == b.stats.free_flight_lookups);
  CHECK(a.stats.transmittance_lookups == b.stats.transmittance_lookups);
  CHECK(a.stats.gradient_lookups == b.stats.gradient_lookups);
  CHECK(a.stats.real_collisions == b.stats.real_collisions);
  CHECK(a.stats.null_collisions == b.stats.null_collisions);
  CHECK(a.stats.stalled_paths == b.stats.stalled_paths);
  CHECK(a.stats.nan_voxels_seen == b.stats.nan_voxels_seen);
  CHECK(a.stats.tiles_skipped == b.stats.tiles_skipped);
}

FieldView view_of(const std::vector<unsigned char>& bytes, DType dt) {
  return FieldView::contiguous(bytes.data(), dt, NX, NY, NZ);
}

}  // namespace

TEST_CASE("paged render equals the plain render bit for bit, every dtype", "[paged]") {
  for (DType dt : {DType::UInt8, DType::Int16, DType::UInt16, DType::Float32, DType::Float64}) {
    const auto bytes = make_field(dt);
    const FieldView whole = view_of(bytes, dt);
    const tessera::SceneDesc s = scene_for(dt, Variant{});
    const Result plain = render_plain(whole, s);
    Paging pg;
    pg.lo[0] = 3, pg.lo[1] = 0, pg.lo[2] = 5;
    pg.hi[0] = 11, pg.hi[1] = NY, pg.hi[2] = 6;  // uneven, 1 vertex thick along k
    INFO("dtype " << tessera::dtype_name(dt));
    require_same(plain, render_paged(whole, s, pg));
  }
}

TEST_CASE("paged render equals the plain render across modes", "[paged]") {
  const auto bytes = make_field(DType::Float32);
  const FieldView whole = view_of(bytes, DType::Float32);
  std::vector<std::pair<std::string, Variant>> variants;
  variants.push_back({"multiple, ratio", Variant{}});
  Variant v;
  v.scattering = tessera::Scattering::Single;
  variants.push_back({"single", v});
  v = Variant{};
  v.shadow = tessera::ShadowMode::Delta;
  variants.push_back({"delta shadows", v});
  v = Variant{};
  v.free_path = tessera::FreePath::Raymarch;
  variants.push_back({"raymarch", v});
  v = Variant{};
  v.emission = false;
  variants.push_back({"no emission", v});
  v = Variant{};
  v.target_error = 0.05;
  variants.push_back({"adaptive", v});
  v = Variant{};
  v.majorant = tessera::MajorantMode::Global;
  variants.push_back({"global majorant", v});
  for (const auto& [name, var] : variants) {
    INFO(name);
    tessera::SceneDesc s = scene_for(DType::Float32, var);
    if (var.target_error > 0.0) s.image.spp = 16;
    const Result plain = render_plain(whole, s);
    require_same(plain, render_paged(whole, s, Paging{}));
  }
}

TEST_CASE("paged render equals the plain render for cell data and rectilinear axes", "[paged][cell][rectilinear]") {
  // The global descriptor with its geometry: the same box, bounds, p space and macrocell
  // walls as the plain render, so the same pixels bit for bit
  const auto bytes = make_field(DType::Float32);
  const FieldView whole = view_of(bytes, DType::Float32);
  for (const bool cell : {false, true}) {
    tessera::SceneDesc s = scene_for(DType::Float32, Variant{});
    s.geometry.association = cell ? tessera::Association::Cell : tessera::Association::Vertex;
    // y rectilinear (stretched), x and z uniform
    std::vector<double> y(static_cast<std::size_t>(NY + (cell ? 1 : 0)));
    for (std::size_t j = 0; j < y.size(); ++j)
      y[j] = -0.9 + 0.05 * static_cast<double>(j) + 0.004 * static_cast<double>(j * j);
    s.geometry.coords[1] = y.data();
    INFO((cell ? "cell data" : "vertex data"));
    const Result plain = render_plain(whole, s);
    Paging pg;
    pg.lo[0] = 2, pg.lo[1] = 4, pg.lo[2] = 0;
    pg.hi[0] = NX, pg.hi[1] = 11, pg.hi[2] = 9;
    require_same(plain, render_paged(whole, s, pg));
  }
}

TEST_CASE("paged render: capacities, shifts, threads and own blocks", "[paged]") {
  const auto bytes = make_field(DType::Float64);
  const FieldView whole = view_of(bytes, DType::Float64);
  Variant var;
  var.target_error = 0.05;
  tessera::SceneDesc s = scene_for(DType::Float64, var);
  s.image.spp = 4;
  const Result plain = render_plain(whole, s);
  for (int shift = 1; shift <= 5; ++shift)
    for (std::size_t capacity : {std::size_t{1}, std::size_t{3}, std::size_t{64}})
      for (int threads : {1, 2}) {
        // Small caches of small bricks miss (and flush) at nearly every lookup: ~50 us each
        if ((capacity == 1 && (shift < 3 || shift > 4)) || (capacity == 3 && shift < 2)) continue;
        Paging pg;
        pg.shift = shift;
        pg.capacity = capacity;
        pg.threads = threads;
        if (shift % 2 == 0) {  // a block 1 vertex thick along i; else no own block
          pg.lo[0] = 9, pg.hi[0] = 10;
          pg.hi[1] = NY, pg.hi[2] = NZ;
        }
        INFO("shift " << shift << ", capacity " << capacity << ", threads " << threads);
        tessera::BrickCacheStats cs;
        require_same(plain, render_paged(whole, s, pg, &cs));
        if (capacity == 1) CHECK(cs.flushes > 0);
        CHECK(cs.peak_resident <= capacity);
      }
}

TEST_CASE("paged render: a failing cache ends the render, and failed() says so", "[paged]") {
  const auto bytes = make_field(DType::Float32);
  const FieldView whole = view_of(bytes, DType::Float32);
  tessera::SceneDesc s = scene_for(DType::Float32, Variant{});
  s.options.threads = 2;
  const std::int64_t dims[3] = {NX, NY, NZ};
  tessera::BrickCache cache(tessera::BrickGrid::make(dims, DType::Float32, 2), 2);
  tessera::PagedField f;
  f.dtype = DType::Float32;
  for (int a = 0; a < 3; ++a) f.dims[a] = dims[a];
  f.cache = &cache;
  const auto t0 = std::chrono::steady_clock::now();
  {
    tessera_test::FakeBrickService service(cache, whole, 5);
    const tessera::PreparedScene ps =
        tessera::prepare(f, s, combined_summary(whole, tessera::majorant_edge(whole, s.integrator)));
    tessera::Film film(s.image.width, s.image.height);
    tessera::RenderStats st;
    tessera::render(ps, film, st);
  }
  CHECK(cache.failed());
  CHECK(cache.failure().find("failing after 5") != std::string::npos);
  CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(20));
  cache.reset();
  CHECK_FALSE(cache.failed());
}

TEST_CASE("prepare(PagedField) checks the cache, the block and the summary", "[paged]") {
  const auto bytes = make_field(DType::Float32);
  const FieldView whole = view_of(bytes, DType::Float32);
  const tessera::SceneDesc s = scene_for(DType::Float32, Variant{});
  const std::int64_t dims[3] = {NX, NY, NZ};
  tessera::BrickCache cache(tessera::BrickGrid::make(dims, DType::Float32, 3), 8);
  tessera::PagedField f;
  f.dtype = DType::Float32;
  for (int a = 0; a < 3; ++a) f.dims[a] = dims[a];
  f.cache = &cache;
  const int edge = tessera::majorant_edge(whole, s.integrator);
  REQUIRE_THROWS_WITH(tessera::prepare(f, s, nullptr), Catch::Contains("no field summary"));
  REQUIRE_THROWS_WITH(
      tessera::prepare(f, s, tessera::FieldSummary::build(whole, edge + 1)),
      Catch::Contains("edge " + std::to_string(edge + 1)) && Catch::Contains("needs " + std::to_string(edge)));
  tessera::PagedField g = f;
  g.dtype = DType::Float64;
  REQUIRE_THROWS_WITH(tessera::prepare(g, s, tessera::FieldSummary::build(whole, edge)),
                      Catch::Contains("brick cache is for a float32"));
  g = f;
  g.local = whole;
  g.offset[2] = 1;
  REQUIRE_THROWS_WITH(tessera::prepare(g, s, tessera::FieldSummary::build(whole, edge)),
                      Catch::Contains("not inside the global dims"));
  g = f;
  g.cache = nullptr;
  REQUIRE_THROWS_WITH(tessera::prepare(g, s, tessera::FieldSummary::build(whole, edge)),
                      Catch::Contains("no brick cache"));
}

namespace {

/// A box of global vertices [lo, hi).
struct VBox {
  std::int64_t lo[3], hi[3];
};

FieldView sub_view(const FieldView& whole, const VBox& b) {
  FieldView v = whole;
  v.data = static_cast<const unsigned char*>(whole.data) + b.lo[0] * whole.byte_strides[0] +
           b.lo[1] * whole.byte_strides[1] + b.lo[2] * whole.byte_strides[2];
  for (int a = 0; a < 3; ++a) v.dims[a] = b.hi[a] - b.lo[a];
  return v;
}

/// Renders through a paged field whose own blocks are `boxes` (the first as PagedField::local,
/// the others through BrickCache::set_in_place), the rest served by the fake service.
Result render_blocks(const FieldView& whole, tessera::SceneDesc s, const std::vector<VBox>& boxes, int shift,
                     std::size_t capacity, tessera::BrickCacheStats& cs, std::uint64_t* in_place_vertices = nullptr) {
  s.options.threads = 2;
  const std::int64_t dims[3] = {NX, NY, NZ};
  tessera::BrickCache cache(tessera::BrickGrid::make(dims, whole.dtype, shift), capacity);
  tessera::PagedField f;
  f.dtype = whole.dtype;
  for (int a = 0; a < 3; ++a) f.dims[a] = dims[a];
  f.local = sub_view(whole, boxes[0]);
  for (int a = 0; a < 3; ++a) f.offset[a] = boxes[0].lo[a];
  std::vector<tessera::InPlaceBlock> others;
  for (std::size_t n = 1; n < boxes.size(); ++n) {
    tessera::InPlaceBlock& b = others.emplace_back();
    b.view = sub_view(whole, boxes[n]);
    for (int a = 0; a < 3; ++a) b.offset[a] = boxes[n].lo[a];
  }
  cache.set_in_place(others);
  if (in_place_vertices) *in_place_vertices = cache.in_place_vertices();
  f.cache = &cache;
  const int edge = tessera::majorant_edge(whole, s.integrator);
  Result r;
  {
    tessera_test::FakeBrickService service(cache, whole);
    const tessera::PreparedScene ps = tessera::prepare(f, s, combined_summary(whole, edge));
    r.px = tessera_test::render_film(ps, &r.stats).pixels();
  }
  REQUIRE_FALSE(cache.failed());
  cs = cache.stats();
  return r;
}

/// The whole grid cut at k = kz and, above it, at i = ix and j = jy: four blocks, the
/// largest first.
std::vector<VBox> four_blocks(std::int64_t kz, std::int64_t ix, std::int64_t jy) {
  return {VBox{{0, 0, 0}, {NX, NY, kz}}, VBox{{0, 0, kz}, {ix, jy, NZ}}, VBox{{ix, 0, kz}, {NX, jy, NZ}},
          VBox{{0, jy, kz}, {NX, NY, NZ}}};
}

}  // namespace

TEST_CASE("paged render with several own blocks reads them in place, bit for bit", "[paged][domains]") {
  // Every vertex in one of the own blocks: cuts on even vertices (the table's cells are 2
  // vertices wide on this small grid) leave nothing to fetch, so the cache is never asked;
  // odd cuts leave straddling cells, fetched through the cache, with the same image
  for (DType dt : {DType::UInt8, DType::Float32, DType::Float64}) {
    const auto bytes = make_field(dt);
    const FieldView whole = view_of(bytes, dt);
    const tessera::SceneDesc s = scene_for(dt, Variant{});
    const Result plain = render_plain(whole, s);
    INFO("dtype " << tessera::dtype_name(dt));
    tessera::BrickCacheStats even, odd, alone;
    std::uint64_t in_place = 0;
    require_same(plain, render_blocks(whole, s, four_blocks(6, 8, 10), 3, 4, even, &in_place));
    CHECK(in_place == static_cast<std::uint64_t>(NX * NY * (NZ - 6)));  // every other block's vertex
    CHECK(even.fetched == 0);
    CHECK(even.misses == 0);
    require_same(plain, render_blocks(whole, s, four_blocks(7, 9, 11), 3, 4, odd));
    CHECK(odd.fetched > 0);
    // Only the first block in place (the others through the cache): far more fetches
    require_same(plain, render_blocks(whole, s, {VBox{{0, 0, 0}, {NX, NY, 7}}}, 3, 4, alone));
    CHECK(alone.fetched > odd.fetched);
  }
}

TEST_CASE("paged render: own blocks read in place through negative strides", "[paged][domains]") {
  // The same values stored with j mirrored (a negative j stride), cut on even vertices
  const auto bytes = make_field(DType::Float32);
  const FieldView whole = view_of(bytes, DType::Float32);
  std::vector<unsigned char> mirrored(bytes.size());
  const std::size_t row = static_cast<std::size_t>(NX) * 4;
  for (std::int64_t k = 0; k < NZ; ++k)
    for (std::int64_t j = 0; j < NY; ++j)
      std::memcpy(mirrored.data() + static_cast<std::size_t>((k * NY + (NY - 1 - j))) * row,
                  bytes.data() + static_cast<std::size_t>((k * NY + j)) * row, row);
  FieldView flipped = whole;
  flipped.data = mirrored.data() + static_cast<std::size_t>(NY - 1) * row;
  flipped.byte_strides[1] = -static_cast<std::int64_t>(row);
  const tessera::SceneDesc s = scene_for(DType::Float32, Variant{});
  const Result plain = render_plain(whole, s);
  tessera::BrickCacheStats cs;
  require_same(plain, render_blocks(flipped, s, four_blocks(4, 10, 6), 2, 8, cs));
  CHECK(cs.fetched == 0);
}

TEST_CASE("BrickCache::set_in_place checks its blocks", "[paged][domains]") {
  const auto bytes = make_field(DType::Float32);
  const FieldView whole = view_of(bytes, DType::Float32);
  const std::int64_t dims[3] = {NX, NY, NZ};
  tessera::BrickCache cache(tessera::BrickGrid::make(dims, DType::Float32, 3), 4);
  tessera::InPlaceBlock b;
  b.view = sub_view(whole, VBox{{0, 0, 0}, {4, 4, 4}});
  std::vector<tessera::InPlaceBlock> blocks{b};
  blocks[0].offset[2] = NZ - 3;
  REQUIRE_THROWS_WITH(cache.set_in_place(blocks),
                      Catch::Contains("in-place block 0") && Catch::Contains("not inside the grid"));
  blocks[0].offset[2] = 0;
  blocks.push_back(b);
  blocks[1].offset[0] = 2;  // overlaps block 0 on whole cells
  REQUIRE_THROWS_WITH(cache.set_in_place(blocks),
                      Catch::Contains("in-place block 1") && Catch::Contains("overlaps in-place block 0"));
  CHECK(cache.in_place().cell == nullptr);  // a failed call leaves none
  blocks.pop_back();
  std::vector<double> wide(64);
  blocks[0].view = FieldView::contiguous(wide.data(), DType::Float64, 4, 4, 4);
  REQUIRE_THROWS_WITH(cache.set_in_place(blocks), Catch::Contains("is float64"));
  blocks[0].view = b.view;
  cache.set_in_place(blocks);
  CHECK(cache.in_place_count() == 1);
  CHECK(cache.in_place_vertices() == 64);
  CHECK(cache.in_place().cell != nullptr);
  cache.set_in_place({});
  CHECK(cache.in_place().cell == nullptr);
  // The table's entries are bounded and counted by bytes_for
  CHECK(tessera::BrickCache::in_place_entries(cache.grid()) == (std::uint64_t{1} << 18));
  CHECK(tessera::BrickCache::bytes_for(cache.grid(), 0) >= (std::uint64_t{4} << 18));
}

TEST_CASE("BrickCache::set_in_place takes the finest cells that fit", "[paged][domains]") {
  // 160^3 vertices: cells of 2 would need 80^3 > 2^18 entries, cells of 4 need 40^3. A block
  // of z in [0, 81) then holds the cells up to z = 80 whole (the values are never read here)
  const std::int64_t dims[3] = {160, 160, 160};
  tessera::BrickCache cache(tessera::BrickGrid::make(dims, DType::UInt8, 5), 1);
  std::vector<unsigned char> one(1);
  tessera::InPlaceBlock b;
  b.view = FieldView::contiguous(one.data(), DType::UInt8, 160, 160, 81);
  const tessera::InPlaceBlock blocks[] = {b};
  cache.set_in_place(blocks);
  CHECK(cache.in_place().shift == 2);
  CHECK(cache.in_place().cells[2] == 21);  // the box [0, 81) in cells of 4
  CHECK(cache.in_place_vertices() == 160u * 160u * 80u);
}
