// Refinement levels (amr.h, docs/physics.md "Refinement levels"):
// - a single-level hierarchy renders bit-identically to the same uniform field, however
//   level 0 is cut into patches;
// - the image does not depend on how levels are cut into patches, on their order, on the
//   thread count or on the tile size;
// - a point takes the finest level whose whole stencil is present; a linear field has the
//   same value at every level, and renders the same as a single level (z-test);
// - the majorants bound the extinction along every macrocell the walk reports, over random
//   hierarchies with NaN and infinite samples;
// - malformed hierarchies are refused, naming the patch, level and axis.
//
// Statistics: two-sided z-tests with |z| < 4 (false-alarm probability 6.3e-5 each) between
// two independent renders (own seeds), standard errors from the per-pixel sample variance.
#include <tessera/amr.h>
#include <tessera/render.h>
#include <tessera/scene_warnings.h>

#include <catch2/catch.hpp>

#include "amr_hierarchy.h"
#include "fake_brick_service.h"
#include "kernel/kernel_dispatch.h"
#include "sampling/rng.h"
#include "scene/prepared_scene_impl.h"
#include "test_support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

using tessera::AmrBox;
using tessera::AmrField;
using tessera::AmrPatch;
using tessera::Association;
using tessera::Color;
using tessera::FieldSummary;
using tessera::FieldView;
using tessera::Vec3;

namespace {

using Fn = tessera_test::PositionFn;
using Hierarchy = tessera_test::AmrHierarchy;

AmrBox box(int level, std::int64_t x0, std::int64_t y0, std::int64_t z0, std::int64_t nx, std::int64_t ny,
           std::int64_t nz) {
  AmrBox b;
  b.level = level;
  b.offset[0] = x0;
  b.offset[1] = y0;
  b.offset[2] = z0;
  b.dims[0] = nx;
  b.dims[1] = ny;
  b.dims[2] = nz;
  return b;
}

/// `b` cut along axis a at element `at` (relative to its offset) into two boxes.
std::vector<AmrBox> cut(const AmrBox& b, int a, std::int64_t at) {
  AmrBox lo = b, hi = b;
  lo.dims[a] = at;
  hi.offset[a] += at;
  hi.dims[a] -= at;
  return {lo, hi};
}

/// A scattering scene lit by the background and a sphere light over the bounds b.
tessera::SceneDesc lit_scene(const tessera::VolumeGeometry& g, const tessera::Bounds& b, double lo, double hi) {
  tessera::SceneDesc s;
  s.geometry = g;
  s.tf.lo = lo;
  s.tf.hi = hi;
  s.tf.density_scale = 4.0 / (b.hi.z - b.lo.z);
  s.tf.opacity = tessera::ScalarTF({0.0, 0.5, 1.0}, {0.05, 0.6, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.8, 0.7, 0.6));
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(0.5);
  s.lights.push_back(tessera::SphereLightDesc{b.hi + Vec3(1.0), 0.3, Color(20.0)});
  s.camera.position = b.center() + Vec3(0.3, 0.8, -3.0) * glm::length(b.hi - b.lo);
  s.camera.look_at = b.center();
  s.camera.fov_deg = 30.0;
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 6;
  s.integrator.macrocell = 2;
  s.image = {20, 18, 8, 0.0};
  s.options.seed = 31;
  return s;
}

bool same_pixels(const tessera::Film& a, const tessera::Film& b) {
  return a.pixels().size() == b.pixels().size() &&
         std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(tessera::PixelSums)) == 0;
}

double z_difference(const tessera_test::MeanWithError& a, const tessera_test::MeanWithError& b) {
  return std::fabs(a.mean - b.mean) / std::sqrt(a.se * a.se + b.se * b.se);
}

/// Values that are the same function of position at every level but not linear.
double wavy(const Vec3& x) { return 0.5 + 0.4 * std::sin(3.1 * x.x + 1.3) * std::cos(2.3 * x.y - 0.7 * x.z); }

}  // namespace

TEST_CASE("amr: a single-level hierarchy renders as the uniform field, however level 0 is cut", "[amr][render]") {
  for (const Association assoc : {Association::Vertex, Association::Cell}) {
    const std::int64_t dims[3] = {11, 9, 8};
    Hierarchy one(dims, assoc, {}, Vec3(-0.4, 0.1, 0.3), Vec3(0.1, 0.12, 0.09));
    Hierarchy cut5(dims, assoc, {}, one.origin, one.h);
    tessera::Rng rng(7, 0, 0, 0);
    std::vector<double> values(11 * 9 * 8);
    for (double& v : values) v = rng.uniform();
    const auto at = [&](const Vec3& x) {
      // the random value of the sample at world x (exact: positions are sample positions)
      std::int64_t i[3];
      for (int a = 0; a < 3; ++a)
        i[a] = std::llround((x[a] - one.origin[a]) / one.h[a] - (assoc == Association::Cell ? 0.5 : 0.0));
      return values[static_cast<std::size_t>((i[2] * 9 + i[1]) * 11 + i[0])];
    };
    one.add(box(0, 0, 0, 0, 11, 9, 8), at);
    // Level 0 in 5 uneven pieces, listed out of order
    for (const AmrBox& b : {box(0, 0, 0, 0, 4, 9, 8), box(0, 4, 0, 0, 7, 3, 8), box(0, 4, 3, 0, 7, 6, 2),
                            box(0, 4, 3, 2, 5, 6, 6), box(0, 9, 3, 2, 2, 6, 6)})
      cut5.add(b, at);
    const FieldView whole = FieldView::contiguous(values.data(), tessera::DType::Float64, 11, 9, 8);
    tessera::SceneDesc s = lit_scene(one.geometry(), tessera::field_bounds(whole, one.geometry()), 0.0, 1.0);
    const tessera::Film ref = tessera_test::render_film(tessera::prepare(whole, s));
    const tessera::PreparedScene p1 = tessera::prepare(one.finish(), s, nullptr);
    const tessera::PreparedScene p5 = tessera::prepare(cut5.finish(), s, nullptr);
    INFO((assoc == Association::Cell ? "cell" : "vertex"));
    CHECK(p1.bounds().lo == tessera::prepare(whole, s).bounds().lo);
    CHECK(p1.bounds().hi == tessera::prepare(whole, s).bounds().hi);
    CHECK(same_pixels(tessera_test::render_film(p1), ref));
    CHECK(same_pixels(tessera_test::render_film(p5), ref));
  }
}

TEST_CASE("amr: the image does not depend on the cut into patches, their order, threads or tiles",
          "[amr][render][determinism]") {
  for (const Association assoc : {Association::Vertex, Association::Cell}) {
    const std::int64_t dims[3] = {8, 7, 6};
    const bool cell = assoc == Association::Cell;
    // Level 1 (ratio 2) over coarse [2, 6) x [1, 5) x [1, 5); level 2 (ratio 4) inside it
    const AmrBox l1 = cell ? box(1, 4, 2, 2, 8, 8, 8) : box(1, 4, 2, 2, 7, 7, 7);
    const AmrBox l2 = cell ? box(2, 20, 12, 12, 12, 8, 12) : box(2, 20, 12, 12, 9, 9, 9);
    const std::vector<std::vector<AmrBox>> cuts = {
        {box(0, 0, 0, 0, 8, 7, 6), l1, l2},
        // level 0 in 2, level 1 in 3, level 2 in 2, reversed order
        [&] {
          std::vector<AmrBox> v;
          const auto a = cut(l1, 0, 3), b = cut(a[1], 2, 2), c = cut(l2, 1, 5), d = cut(box(0, 0, 0, 0, 8, 7, 6), 1, 4);
          v = {c[1], c[0], b[1], b[0], a[0], d[1], d[0]};
          return v;
        }()};
    std::vector<tessera::Film> films;
    for (std::size_t c = 0; c < cuts.size(); ++c) {
      Hierarchy h(dims, assoc, {2, 4}, Vec3(0.0), Vec3(0.125));
      for (const AmrBox& b : cuts[c]) h.add(b, wavy);
      const AmrField& f = h.finish();
      tessera::SceneDesc s = lit_scene(h.geometry(), tessera::Bounds{Vec3(0.0), Vec3(1.0, 0.875, 0.75)}, 0.0, 1.0);
      for (const int threads : {1, 3})
        for (const int tile : {8, 5}) {
          if (c == 0 && threads == 3) continue;
          s.options.threads = threads;
          s.options.tile = tile;
          films.push_back(tessera_test::render_film(tessera::prepare(f, s, nullptr)));
        }
    }
    INFO((cell ? "cell" : "vertex"));
    for (std::size_t n = 1; n < films.size(); ++n) CHECK(same_pixels(films[n], films[0]));
    CHECK(tessera_test::luminance_stats(films[0]).mean > 0.0);
  }
}

TEST_CASE("amr: a point takes the finest level whose whole stencil is present", "[amr][medium]") {
  // Level 0 holds f, level 1 holds f + 1 (ratio 2), so the value tells the level. f linear:
  // every level reproduces it exactly, so v - f is 0 or 1 up to rounding.
  const auto f = [](const Vec3& x) { return 0.3 * x.x - 0.2 * x.y + 0.1 * x.z; };
  for (const Association assoc : {Association::Vertex, Association::Cell}) {
    const bool cell = assoc == Association::Cell;
    const std::int64_t dims[3] = {10, 10, 10};
    Hierarchy h(dims, assoc, {2}, Vec3(0.0), Vec3(1.0));
    h.add(box(0, 0, 0, 0, 10, 10, 10), f);
    const AmrBox fine = cell ? box(1, 6, 4, 8, 6, 8, 8) : box(1, 6, 4, 8, 5, 7, 7);
    h.add(fine, [&](const Vec3& x) { return f(x) + 1.0; });
    tessera::SceneDesc s;
    s.geometry = h.geometry();
    s.tf.lo = -5.0;
    s.tf.hi = 5.0;
    s.camera.position = Vec3(5.0, 5.0, -30.0);
    const tessera::PreparedScene ps = tessera::prepare(h.finish(), s, nullptr);
    const tessera::KernelScene& ks = tessera::prepared_scene_impl(ps).kernel;
    REQUIRE(ks.amr.nlevels == 2);
    const auto m = tessera::make_medium<tessera::AmrValue>(ks);
    tessera::Rng rng(5, 0, 0, 0);
    int fine_hits = 0, coarse_hits = 0, bad = 0;
    for (int t = 0; t < 20000; ++t) {
      Vec3 p;  // level-0 p space over the centres' (or vertices') box
      for (int a = 0; a < 3; ++a) p[a] = 9.0 * rng.uniform();
      const Vec3 x = cell ? p + Vec3(0.5) : p;  // world position (origin 0, spacing 1)
      // The fine stencil is present iff q = p R + shift lies between the fine patch's first
      // and last samples along every axis
      bool inside = true;
      for (int a = 0; a < 3; ++a) {
        const double q = p[a] * 2.0 + (cell ? 0.5 : 0.0);
        inside = inside && q >= static_cast<double>(fine.offset[a]) &&
                 q <= static_cast<double>(fine.offset[a] + fine.dims[a] - 1);
      }
      const double d = m.value(p) - f(x);
      (inside ? fine_hits : coarse_hits)++;
      if (std::fabs(d - (inside ? 1.0 : 0.0)) > 1e-9) ++bad;
    }
    INFO((cell ? "cell" : "vertex"));
    CHECK(fine_hits > 500);
    CHECK(coarse_hits > 500);
    CHECK(bad == 0);
  }
}

TEST_CASE("amr: a linear field has the same value at every level and renders as one level",
          "[amr][render][statistical]") {
  const auto f = [](const Vec3& x) { return 0.2 + 0.5 * x.x + 0.3 * x.y + 0.2 * x.z; };
  for (const Association assoc : {Association::Vertex, Association::Cell}) {
    const bool cell = assoc == Association::Cell;
    const std::int64_t dims[3] = {8, 8, 8};
    const Vec3 h0(1.0 / 8.0);
    // Three levels: ratio 2 then 4, the finest over a corner region
    Hierarchy h(dims, assoc, {2, 4}, Vec3(0.0), h0);
    h.add(box(0, 0, 0, 0, 8, 8, 8), f);
    for (const AmrBox& b : cut(cell ? box(1, 2, 2, 2, 10, 12, 10) : box(1, 2, 2, 2, 9, 11, 9), 2, 4)) h.add(b, f);
    h.add(cell ? box(2, 16, 16, 16, 16, 24, 16) : box(2, 16, 16, 16, 17, 25, 17), f);
    const AmrField& field = h.finish();
    // The same function on level 0 alone
    std::vector<double> level0;
    for (int k = 0; k < 8; ++k)
      for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) {
          const std::int64_t idx[3] = {i, j, k};
          level0.push_back(f(h.position(0, idx)));
        }
    const FieldView view = FieldView::contiguous(level0.data(), tessera::DType::Float64, 8, 8, 8);
    tessera::SceneDesc s = lit_scene(h.geometry(), tessera::field_bounds(view, h.geometry()), 0.0, 1.2);
    s.integrator.shading = tessera::Shading::Brdf;
    s.image = {20, 20, 48, 0.0};
    // Values: the linear function at points of every level's region
    const tessera::PreparedScene pa = tessera::prepare(field, s, nullptr);
    const auto m = tessera::make_medium<tessera::AmrValue>(tessera::prepared_scene_impl(pa).kernel);
    tessera::Rng rng(17, 0, 0, 0);
    double worst = 0.0;
    for (int t = 0; t < 5000; ++t) {
      Vec3 p;
      for (int a = 0; a < 3; ++a) p[a] = 7.0 * rng.uniform();
      worst = std::max(worst, std::fabs(m.value(p) - f(h.origin + (cell ? p + Vec3(0.5) : p) * h0)));
    }
    CHECK(worst < 1e-12);
    // Renders: the hierarchy against level 0 alone
    s.options.seed = 100;
    const auto La = tessera_test::luminance_stats(tessera_test::render_film(pa));
    s.options.seed = 200;
    const auto L0 = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(view, s)));
    INFO((cell ? "cell" : "vertex") << ": levels " << La.mean << " +- " << La.se << ", level 0 " << L0.mean << " +- "
                                    << L0.se);
    CHECK(La.se > 0.0);
    CHECK(z_difference(La, L0) < 4.0);
  }
}

TEST_CASE("amr: a non-linear field renders differently once refined", "[amr][render]") {
  // The finer level holds detail level 0 cannot: sin^2(6 pi x) is 1 at every level-0 centre
  // and averages 1/2 over the level-1 centres, so the refined medium is thinner and the
  // image must change (levels reach the renderer)
  const std::int64_t dims[3] = {6, 6, 6};
  const auto sharp = [](const Vec3& x) { return std::pow(std::sin(6.0 * tessera::kPi * x.x), 2.0); };
  Hierarchy one(dims, Association::Cell, {4}, Vec3(0.0), Vec3(1.0 / 6.0));
  one.add(box(0, 0, 0, 0, 6, 6, 6), sharp);
  Hierarchy two(dims, Association::Cell, {4}, Vec3(0.0), Vec3(1.0 / 6.0));
  two.add(box(0, 0, 0, 0, 6, 6, 6), sharp);
  two.add(box(1, 0, 0, 0, 24, 24, 24), sharp);
  tessera::SceneDesc s = lit_scene(one.geometry(), tessera::Bounds{Vec3(0.0), Vec3(1.0)}, 0.0, 1.0);
  s.image = {16, 16, 32, 0.0};
  s.tf.density_scale = 2.0;  // an absorber in front of a white background: the image is transmittance
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.0));
  s.background.color = Color(1.0);
  s.lights.clear();
  const auto L1 = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(one.finish(), s, nullptr)));
  s.options.seed = 77;
  const auto L2 = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(two.finish(), s, nullptr)));
  INFO("level 0 " << L1.mean << " +- " << L1.se << ", refined " << L2.mean << " +- " << L2.se);
  CHECK(z_difference(L1, L2) > 6.0);
}

TEST_CASE("amr: majorants bound the extinction along the walk over random hierarchies", "[amr][majorant]") {
  tessera::Rng rng(2026, 0, 0, 0);
  int bad = 0, segments = 0, fine_trials = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const Association assoc = trial % 2 ? Association::Cell : Association::Vertex;
    const bool cell = assoc == Association::Cell;
    std::int64_t dims[3];
    for (int a = 0; a < 3; ++a) dims[a] = 2 + static_cast<std::int64_t>(rng.uniform() * 9.0);
    const int nlevels = 2 + trial % 3;
    std::vector<int> ratios;
    for (int l = 0; l + 1 < nlevels; ++l) ratios.push_back(rng.uniform() < 0.5 ? 2 : 4);
    Hierarchy h(dims, assoc, ratios, Vec3(-0.3, 0.2, 1.0), Vec3(0.2, 0.35, 0.1));
    // Level 0 in two pieces; each finer level: one random sub-box of a random patch of the
    // level above, refined, sometimes cut in two
    const auto noisy = [&](const Vec3&) -> double {
      const double u = rng.uniform();
      if (u < 0.01) return std::nan("");
      if (u < 0.015) return INFINITY;
      if (u < 0.02) return -INFINITY;
      return rng.uniform();
    };
    std::vector<AmrBox> boxes;
    const AmrBox whole = box(0, 0, 0, 0, dims[0], dims[1], dims[2]);
    const int axis0 = trial % 3;
    if (dims[axis0] > 1)
      for (const AmrBox& b : cut(whole, axis0, dims[axis0] / 2)) boxes.push_back(b);
    else boxes.push_back(whole);
    for (int l = 1; l < nlevels; ++l) {
      std::vector<AmrBox> above;
      for (const AmrBox& b : boxes)
        if (b.level == l - 1) above.push_back(b);
      const AmrBox& parent = above[static_cast<std::size_t>(rng.uniform() * static_cast<double>(above.size()))];
      const std::int64_t r = ratios[static_cast<std::size_t>(l - 1)];
      AmrBox c;
      c.level = l;
      bool ok = true;
      for (int a = 0; a < 3; ++a) {
        const std::int64_t need = cell ? 1 : 2;  // coarse elements the fine box spans at least
        if (parent.dims[a] < need) ok = false;
        const std::int64_t len = need + static_cast<std::int64_t>(rng.uniform() * double(parent.dims[a] - need + 1));
        const std::int64_t lo =
            parent.offset[a] +
            static_cast<std::int64_t>(rng.uniform() * double(parent.dims[a] - std::min(len, parent.dims[a]) + 1));
        const std::int64_t l_len = std::min(len, parent.offset[a] + parent.dims[a] - lo);
        c.offset[a] = lo * r;
        c.dims[a] = cell ? l_len * r : (l_len - 1) * r + 1;
        if (c.dims[a] < 1) ok = false;
      }
      if (!ok) break;
      if (c.dims[trial % 3] > 2 && rng.uniform() < 0.5)
        for (const AmrBox& b : cut(c, trial % 3, c.dims[trial % 3] / 2)) boxes.push_back(b);
      else boxes.push_back(c);
      fine_trials += l == nlevels - 1;
    }
    for (const AmrBox& b : boxes) h.add(b, noisy);
    const AmrField& field = h.finish();
    tessera::SceneDesc s;
    s.geometry = h.geometry();
    s.tf.density_scale = 0.5 + 20.0 * rng.uniform();
    s.tf.opacity =
        tessera::ScalarTF({0.0, 0.3, 0.6, 1.0}, {rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()});
    s.camera.position = Vec3(0.0, 0.0, -10.0);
    s.integrator.majorant = tessera::MajorantMode::Grid;
    s.integrator.macrocell = 1 + trial % 4;
    const tessera::PreparedScene ps = tessera::prepare(field, s, nullptr);
    const tessera::KernelScene& ks = tessera::prepared_scene_impl(ps).kernel;
    tessera_test::walk_rays(tessera::make_medium<tessera::AmrValue>(ks), cell, rng, bad, segments);
  }
  CHECK(fine_trials > 10);
  CHECK(segments > 1000);
  CHECK(bad == 0);
}

TEST_CASE("amr: malformed hierarchies are refused, naming the patch, level and axis", "[amr][robustness]") {
  const std::int64_t dims[3] = {4, 4, 4};
  struct Case {
    std::vector<int> ratios;
    std::vector<AmrBox> boxes;
    std::string expect;
  };
  const AmrBox l0 = box(0, 0, 0, 0, 4, 4, 4);
  const std::vector<Case> cases = {
      {{3}, {l0}, "refinement[0] = 3"},
      {{2}, {l0, box(2, 0, 0, 0, 2, 2, 2)}, "patch 1: level 2 is outside [0, 2)"},
      {{2}, {l0, box(-1, 0, 0, 0, 2, 2, 2)}, "patch 1: level -1"},
      {{2}, {box(0, 0, 0, 0, 4, 4, 3)}, "level 0 does not cover the mesh"},
      {{2}, {l0, box(0, 0, 0, 0, 1, 1, 1)}, "patch 0 and patch 1 overlap at level 0"},
      {{2}, {l0, box(1, 0, 0, 0, 4, 4, 4), box(1, 2, 2, 2, 3, 3, 3)}, "overlap at level 1"},
      {{2}, {l0, box(1, 5, 0, 0, 3, 2, 2)}, "along x leave level 1's extent [0, 7)"},
      {{2}, {l0, box(1, 0, 0, -1, 2, 2, 2)}, "along z leave level 1"},
      {{2, 2}, {l0, box(1, 0, 0, 0, 3, 3, 3), box(2, 4, 0, 0, 5, 3, 3)}, "patch 2 (level 2"},
  };
  for (const Case& c : cases) {
    AmrField meta;
    for (int a = 0; a < 3; ++a) meta.dims[a] = dims[a];
    meta.nlevels = static_cast<int>(c.ratios.size()) + 1;
    for (std::size_t l = 0; l < c.ratios.size(); ++l) meta.ratio[l] = c.ratios[l];
    INFO(c.expect);
    try {
      tessera::check_amr_boxes(meta, Association::Vertex, c.boxes,
                               [](std::size_t n) { return "patch " + std::to_string(n); });
      FAIL("accepted");
    } catch (const std::invalid_argument& e) {
      CHECK_THAT(e.what(), Catch::Contains(c.expect));
    }
  }
  // nlevels out of range, and a patch of another dtype through check_amr
  AmrField meta;
  for (int a = 0; a < 3; ++a) meta.dims[a] = 4;
  meta.nlevels = 9;
  CHECK_THROWS_WITH(tessera::check_amr_boxes(meta, Association::Cell, {}, [](std::size_t) { return ""; }),
                    Catch::Contains("nlevels 9"));
  std::vector<float> f(64, 0.0f);
  AmrPatch p;
  p.view = FieldView::contiguous(f.data(), tessera::DType::Float32, 4, 4, 4);
  meta.nlevels = 1;
  meta.dtype = tessera::DType::Float64;
  meta.patches = std::span<const AmrPatch>(&p, 1);
  CHECK_THROWS_WITH(tessera::check_amr(meta, Association::Vertex), Catch::Contains("patch 0 is float32"));
  // Rectilinear axes with levels: not yet
  meta.dtype = tessera::DType::Float32;
  tessera::SceneDesc s;
  const double xs[4] = {0.0, 1.0, 2.5, 3.0};
  s.geometry.coords[0] = xs;
  CHECK_THROWS_WITH(tessera::prepare(meta, s, nullptr), Catch::Contains("not supported yet"));
}

TEST_CASE("amr: distributed mode (other patches through the brick cache) renders the replicated image",
          "[amr][render][paged]") {
  for (const Association assoc : {Association::Vertex, Association::Cell}) {
    const bool cell = assoc == Association::Cell;
    const std::int64_t dims[3] = {8, 7, 6};
    Hierarchy h(dims, assoc, {2, 4}, Vec3(0.0), Vec3(0.125));
    const AmrBox l1 = cell ? box(1, 4, 2, 2, 8, 8, 8) : box(1, 4, 2, 2, 7, 7, 7);
    const AmrBox l2 = cell ? box(2, 20, 12, 12, 12, 8, 12) : box(2, 20, 12, 12, 9, 9, 9);
    std::vector<AmrBox> boxes = cut(box(0, 0, 0, 0, 8, 7, 6), 1, 4);
    for (const AmrBox& b : cut(l1, 0, 3)) boxes.push_back(b);
    for (const AmrBox& b : cut(l2, 2, 5)) boxes.push_back(b);
    for (const AmrBox& b : boxes) h.add(b, wavy);
    const AmrField& whole = h.finish();
    tessera::SceneDesc s = lit_scene(h.geometry(), tessera::Bounds{Vec3(0.0), Vec3(1.0, 0.875, 0.75)}, 0.0, 1.0);
    s.options.threads = 2;
    const tessera::Film ref = tessera_test::render_film(tessera::prepare(whole, s, nullptr));
    // The virtual grid holding every patch, as the other ranks would serve it
    const int shift = 2;
    const tessera::AmrVirtualLayout layout = tessera::amr_virtual_layout(whole, assoc, boxes, shift);
    std::vector<double> grid(static_cast<std::size_t>(layout.dims[0] * layout.dims[1] * layout.dims[2]), -7.0);
    for (std::size_t n = 0; n < boxes.size(); ++n) {
      const AmrBox& b = boxes[n];
      std::size_t q = 0;
      for (std::int64_t k = 0; k < b.dims[2]; ++k)
        for (std::int64_t j = 0; j < b.dims[1]; ++j)
          for (std::int64_t i = 0; i < b.dims[0]; ++i) {
            const std::int64_t x = layout.base[b.level][0] + b.offset[0] + i;
            const std::int64_t y = layout.base[b.level][1] + b.offset[1] + j;
            const std::int64_t z = layout.base[b.level][2] + b.offset[2] + k;
            REQUIRE(x < layout.dims[0]);
            REQUIRE(y < layout.dims[1]);
            REQUIRE(z < layout.dims[2]);
            grid[static_cast<std::size_t>((z * layout.dims[1] + y) * layout.dims[0] + x)] = h.data[n][q++];
          }
    }
    const FieldView grid_view =
        FieldView::contiguous(grid.data(), tessera::DType::Float64, layout.dims[0], layout.dims[1], layout.dims[2]);
    const tessera::BrickGrid bg = tessera::BrickGrid::make(layout.dims, tessera::DType::Float64, shift);
    for (const int own : {0, 1, 2}) {  // patches this rank holds: none, every other one, all but the first
      std::vector<AmrPatch> patches(h.patches);
      for (std::size_t n = 0; n < patches.size(); ++n) {
        const bool mine = own == 2 ? n != 0 : (own == 1 && n % 2 == 0);
        if (!mine) patches[n].view.data = nullptr;
      }
      AmrField d = whole;
      d.patches = patches;
      tessera::BrickCache cache(bg, 6);  // a few slots: flushes too
      d.cache = &cache;
      d.layout = layout;
      const int edge =
          tessera::majorant_edge(FieldView::contiguous(nullptr, tessera::DType::Float64, 8, 7, 6), s.integrator);
      // The summary from this rank's parts and the others' (as the ranks would combine them)
      FieldSummary::Parts mine = tessera::amr_summary_parts(d, assoc, edge);
      AmrField others = whole;
      std::vector<AmrPatch> theirs(h.patches);
      for (std::size_t n = 0; n < theirs.size(); ++n)
        if (patches[n].view.data != nullptr) theirs[n].view.data = nullptr;
      others.patches = theirs;
      others.cache = &cache;
      const FieldSummary::Parts rest = tessera::amr_summary_parts(others, assoc, edge);
      for (std::size_t c = 0; c < mine.lo.size(); ++c) {
        mine.lo[c] = std::min(mine.lo[c], rest.lo[c]);
        mine.hi[c] = std::max(mine.hi[c], rest.hi[c]);
        mine.flags[c] |= rest.flags[c];
      }
      mine.nan += rest.nan;
      mine.vmin = std::min(mine.vmin, rest.vmin);
      mine.vmax = std::max(mine.vmax, rest.vmax);
      tessera::FieldLayout fl;
      fl.dtype = tessera::DType::Float64;
      const auto summary = FieldSummary::from_parts(std::move(mine), fl, edge);
      tessera_test::FakeBrickService service(cache, grid_view);
      const tessera::Film film = tessera_test::render_film(tessera::prepare(d, s, summary));
      INFO((cell ? "cell" : "vertex") << ", own " << own << ": " << cache.stats().fetched << " bricks fetched");
      CHECK(cache.stats().fetched > 0);
      CHECK(same_pixels(film, ref));
    }
  }
}

TEST_CASE("amr: the NaN warning counts the samples of every level", "[amr][warnings]") {
  const std::int64_t dims[3] = {4, 4, 4};
  Hierarchy h(dims, Association::Cell, {2}, Vec3(0.0), Vec3(0.25));
  h.add(box(0, 0, 0, 0, 4, 4, 4), wavy);                                      // 64 samples
  h.add(box(1, 2, 2, 2, 4, 4, 2), [](const Vec3&) { return std::nan(""); });  // 32 NaN samples
  tessera::SceneDesc s = lit_scene(h.geometry(), tessera::Bounds{Vec3(0.0), Vec3(1.0)}, 0.0, 1.0);
  const tessera::PreparedScene ps = tessera::prepare(h.finish(), s, nullptr);
  CHECK(ps.summary()->element_count() == 96);
  CHECK(ps.summary()->nan_vertices() == 32);
  bool found = false;
  for (const std::string& w : tessera::scene_warnings(ps))
    found = found || w.find("32 of 96 vertices") != std::string::npos;
  CHECK(found);
}
