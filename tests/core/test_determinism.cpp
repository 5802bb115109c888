// Determinism (docs/physics.md "Random numbers and determinism"): every sample's random
// stream depends only on (seed, frame, pixel, sample index), so a scene renders to
// bit-identical pixels for any thread count, tile edge, tile order, and any split of the tile
// list across render_tiles calls.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "test_support.h"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

namespace {

constexpr int NX = 20, NY = 18, NZ = 16;

/// Heterogeneous field, hybrid shading with specular, emission, a rect light, a sphere light
/// and a gradient background: every code path of the estimator is exercised.
tessera::SceneDesc busy_scene(tessera::Scattering scattering) {
  tessera::SceneDesc s;
  s.geometry.origin = Vec3(-1.0, -0.9, -0.8);
  s.geometry.spacing = Vec3(0.1);
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = 15.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.15, 0.5, 1.0}, {0.0, 0.3, 0.8, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.9, 0.6, 0.3), Color(0.3, 0.7, 0.95)});
  s.tf.specular = tessera::ColorTF::constant(Color(0.04));
  s.tf.roughness = tessera::ScalarTF({0.0, 1.0}, {0.2, 0.7});
  s.tf.emission = tessera::ColorTF({0.0, 0.6, 1.0}, {Color(0.0), Color(0.0), Color(2.0, 0.5, 0.1)});
  s.camera.position = Vec3(1.5, 1.0, -3.0);
  s.camera.look_at = Vec3(0.0, 0.0, 0.0);
  s.camera.fov_deg = 40.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.0, 2.0, 0.0), Vec3(0.0, 0.0, 0.0), 1.5, 1.0, Color(5.0, 4.0, 3.0)});
  s.lights.push_back(tessera::SphereLightDesc{Vec3(-2.0, 0.5, -1.0), 0.4, Color(3.0, 3.0, 6.0)});
  s.background.type = tessera::BackgroundType::Gradient;
  s.background.top = Color(0.4, 0.5, 0.8);
  s.background.middle = Color(0.3);
  s.background.bottom = Color(0.05);
  s.background.up = Vec3(0.0, 1.0, 0.0);
  s.integrator.scattering = scattering;
  s.integrator.max_bounces = 12;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.gradient_factor = 2.0;
  s.integrator.phase_g = 0.2;
  s.integrator.macrocell = 4;
  s.image = {37, 29, 3, 0.0};  // odd sizes: partial tiles on the right and bottom
  s.options.seed = 4242;
  s.options.frame = 3;
  return s;
}

struct Rendered {
  tessera::Image image;
  tessera::RenderStats stats;
};

Rendered render_with(const FieldView& view, tessera::SceneDesc s, int threads, int tile, tessera::TileOrder order) {
  s.options.threads = threads;
  s.options.tile = tile;
  s.options.order = order;
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  Rendered r;
  const tessera::Film film = tessera_test::render_film(ps, &r.stats);
  r.image = film.resolve();
  return r;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

bool same_image(const tessera::Image& a, const tessera::Image& b) {
  return a.width == b.width && a.height == b.height && same_bits(a.rgba, b.rgba) && same_bits(a.variance, b.variance) &&
         same_bits(a.samples, b.samples);
}

bool same_counters(const tessera::RenderStats& a, const tessera::RenderStats& b) {
  return a.samples == b.samples && a.free_flight_lookups == b.free_flight_lookups &&
         a.transmittance_lookups == b.transmittance_lookups && a.gradient_lookups == b.gradient_lookups &&
         a.real_collisions == b.real_collisions && a.null_collisions == b.null_collisions &&
         a.discarded_samples == b.discarded_samples;
}

}  // namespace

TEST_CASE("bit-identical images for any thread count, tile edge and tile order", "[determinism][render]") {
  const std::vector<float> field = tessera_test::blobby_field(NX, NY, NZ);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, NX, NY, NZ);
  for (const auto sc : {tessera::Scattering::Single, tessera::Scattering::Multiple}) {
    const tessera::SceneDesc s = busy_scene(sc);
    const Rendered ref = render_with(view, s, 1, 8, tessera::TileOrder::RowMajor);
    // The scene is not trivial: light, emission and surface events all happen.
    REQUIRE(ref.stats.real_collisions > 0);
    REQUIRE(ref.stats.gradient_lookups > 0);
    REQUIRE(ref.stats.null_collisions > 0);
    REQUIRE(*std::max_element(ref.image.rgba.begin(), ref.image.rgba.end()) > 0.0f);
    for (const int threads : {1, 2}) {
      for (const int tile : {1, 8, 64, 0}) {
        for (const auto order : {tessera::TileOrder::RowMajor, tessera::TileOrder::Morton}) {
          const Rendered r = render_with(view, s, threads, tile, order);
          INFO((sc == tessera::Scattering::Single ? "single" : "multiple")
               << " threads " << threads << " tile " << tile << " order "
               << (order == tessera::TileOrder::Morton ? "morton" : "row-major"));
          CHECK(same_image(r.image, ref.image));
          CHECK(same_counters(r.stats, ref.stats));
        }
      }
    }
  }
}

TEST_CASE("render_tiles over two halves in reverse order equals render()", "[determinism][render]") {
  const std::vector<float> field = tessera_test::blobby_field(NX, NY, NZ);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, NX, NY, NZ);
  for (const auto sc : {tessera::Scattering::Single, tessera::Scattering::Multiple}) {
    tessera::SceneDesc s = busy_scene(sc);
    s.options.threads = 2;
    s.options.tile = 8;
    const tessera::PreparedScene ps = tessera::prepare(view, s);
    tessera::Film whole(s.image.width, s.image.height);
    tessera::RenderStats st_whole;
    tessera::render(ps, whole, st_whole);

    const int nt = static_cast<int>(ps.tiles().size());
    std::vector<int> first(nt / 2), second(nt - nt / 2);
    std::iota(first.begin(), first.end(), 0);
    std::iota(second.begin(), second.end(), nt / 2);
    std::reverse(first.begin(), first.end());
    tessera::Film split(s.image.width, s.image.height);
    tessera::RenderStats st_split;
    tessera::render_tiles(ps, second, split, st_split);  // the second half first
    tessera::render_tiles(ps, first, split, st_split);
    CHECK(same_image(split.resolve(), whole.resolve()));
    CHECK(same_counters(st_split, st_whole));
    CHECK(st_split.tiles_total == st_whole.tiles_total);
  }
}

TEST_CASE("successive renders continue the sample sequence: 2 x spp equals one 2*spp render", "[determinism][render]") {
  const std::vector<float> field = tessera_test::blobby_field(NX, NY, NZ);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, NX, NY, NZ);
  tessera::SceneDesc s = busy_scene(tessera::Scattering::Multiple);
  s.image.spp = 2;
  const tessera::PreparedScene twice = tessera::prepare(view, s);
  tessera::Film a(s.image.width, s.image.height);
  tessera::RenderStats st;
  tessera::render(twice, a, st);
  tessera::render(twice, a, st);
  s.image.spp = 4;
  s.options.tile = 0;  // and a different tiling on top
  const tessera::PreparedScene once = tessera::prepare(view, s);
  tessera::Film b(s.image.width, s.image.height);
  tessera::render(once, b, st);
  CHECK(same_image(a.resolve(), b.resolve()));
}

TEST_CASE("seed and frame select different random streams", "[determinism][render]") {
  const std::vector<float> field = tessera_test::blobby_field(NX, NY, NZ);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, NX, NY, NZ);
  const tessera::SceneDesc s = busy_scene(tessera::Scattering::Single);
  const Rendered ref = render_with(view, s, 2, 8, tessera::TileOrder::RowMajor);
  tessera::SceneDesc other_frame = s;
  other_frame.options.frame += 1;
  tessera::SceneDesc other_seed = s;
  other_seed.options.seed += 1;
  CHECK_FALSE(same_bits(render_with(view, other_frame, 2, 8, tessera::TileOrder::RowMajor).image.rgba, ref.image.rgba));
  CHECK_FALSE(same_bits(render_with(view, other_seed, 2, 8, tessera::TileOrder::RowMajor).image.rgba, ref.image.rgba));
}

TEST_CASE("adaptive sampling: bit-identical for any thread count, tile edge, order and split",
          "[determinism][render][adaptive]") {
  // Adaptive counts come from 8x8 pixel blocks that tiles of edge 1, 3 or 0 (scanline) cut
  // through: those tiles redraw their neighbours' pilot samples, which must be the same ones.
  const std::vector<float> field = tessera_test::blobby_field(NX, NY, NZ);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, NX, NY, NZ);
  tessera::SceneDesc s = busy_scene(tessera::Scattering::Multiple);
  s.image = {37, 29, 48, 0.1};
  // Both samplers: with independent streams some pixels' counts reach spp (the clamp binds);
  // with the Sobol' sampler (the default) the same blocks' pilots give other counts, up to 43
  const tessera::SamplerKind sampler = GENERATE(tessera::SamplerKind::Independent, tessera::SamplerKind::Sobol);
  s.integrator.sampler = sampler;
  const Rendered ref = render_with(view, s, 1, 8, tessera::TileOrder::RowMajor);
  // The counts do vary: some pixels stop at the pilot, some take more, some all 48.
  const auto [lo, hi] = std::minmax_element(ref.image.samples.begin(), ref.image.samples.end());
  REQUIRE(*lo == 8.0f);  // the pilot: min(spp, max(8, spp / 16))
  if (sampler == tessera::SamplerKind::Independent) REQUIRE(*hi == 48.0f);
  else REQUIRE(*hi > 16.0f);
  REQUIRE(std::count(ref.image.samples.begin(), ref.image.samples.end(), 48.0f) <
          static_cast<long>(ref.image.samples.size()));
  for (const int threads : {1, 2}) {
    for (const int tile : {1, 3, 16, 64, 0}) {
      for (const auto order : {tessera::TileOrder::RowMajor, tessera::TileOrder::Morton}) {
        const Rendered r = render_with(view, s, threads, tile, order);
        INFO("threads " << threads << " tile " << tile);
        CHECK(same_image(r.image, ref.image));
        CHECK(r.stats.samples == ref.stats.samples);
      }
    }
  }
  // Tiles rendered in several calls in a scrambled order (as MPI ranks grab them), with tiles
  // that cut through the blocks: a redrawn pilot must be the owner's, whatever the film
  // already holds from earlier calls.
  for (const int tile : {8, 3}) {
    s.options.tile = tile;
    const tessera::PreparedScene ps = tessera::prepare(view, s);
    const int n = static_cast<int>(ps.tiles().size());
    tessera::Film split(s.image.width, s.image.height);
    tessera::RenderStats st;
    for (int part = 4; part >= 0; --part) {
      std::vector<int> mine;
      for (int i = part; i < n; i += 5) mine.push_back(i);
      tessera::render_tiles(ps, mine, split, st);
    }
    INFO("split into 5 calls, tile " << tile << ", sampler " << static_cast<int>(sampler));
    CHECK(same_image(split.resolve(), ref.image));
  }
}
