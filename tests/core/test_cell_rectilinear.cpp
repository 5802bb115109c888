// Cell-centred data and rectilinear axes (docs/physics.md, "Cell data and rectilinear axes"):
// - cell data equals the clamped trilinear reconstruction of a vertex field placed at the cell
//   centres, bit for bit at every point of the cells' box; the outer half cell renders as the
//   clamped value (Beer-Lambert through the whole cells' box);
// - a linear field on stretched axes renders as on a uniform grid, and its transmittance
//   along a rectilinear axis matches the analytic integral;
// - the majorants bound the extinction along every macrocell the walk reports;
// - images are bit-identical across thread counts and tile sizes.
//
// Statistics: every comparison is a two-sided z-test with |z| < 4 (per-test false-alarm
// probability 6.3e-5); standard errors from the film's per-pixel sample variance (two
// independent renders: sqrt(se1^2 + se2^2)). Seeds are fixed, so outcomes are reproducible.
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "kernel/kernel_dispatch.h"
#include "sampling/rng.h"
#include "scene/prepared_scene_impl.h"
#include "test_support.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using tessera::Association;
using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

namespace {

/// count increasing coordinates from lo to hi, each interval `ratio` times the previous one.
std::vector<double> stretched(int count, double lo, double hi, double ratio) {
  std::vector<double> c(static_cast<std::size_t>(count));
  double w = 1.0, total = 0.0;
  std::vector<double> widths;
  for (int i = 0; i + 1 < count; ++i, w *= ratio) {
    widths.push_back(w);
    total += w;
  }
  c[0] = lo;
  for (int i = 1; i < count; ++i)
    c[static_cast<std::size_t>(i)] =
        c[static_cast<std::size_t>(i) - 1] + (hi - lo) * widths[static_cast<std::size_t>(i) - 1] / total;
  c.back() = hi;
  return c;
}

/// A camera on the box's axis 10 depths in front of it looking along +z, whose footprint on
/// the back face stays within 40% of the box's half-width: every ray crosses the box through
/// its front and back faces.
void frame_box(tessera::SceneDesc& s, const tessera::Bounds& b) {
  const Vec3 c = b.center();
  const double depth = b.hi.z - b.lo.z, half = 0.5 * std::min(b.hi.x - b.lo.x, b.hi.y - b.lo.y);
  s.camera.position = Vec3(c.x, c.y, b.lo.z - 10.0 * depth);
  s.camera.look_at = Vec3(c.x, c.y, b.lo.z);
  s.camera.fov_deg = 2.0 * std::atan(0.4 * half / (11.0 * depth)) * 180.0 / tessera::kPi;
}

/// Mean transmittance over the image for an optical depth tau_z along +z through the box.
double expected_transmittance(const tessera::SceneDesc& s, double tau_z) {
  const tessera::Camera cam(s.camera, s.image.width, s.image.height);
  double sum = 0.0;
  int n = 0;
  for (int y = 0; y < s.image.height; ++y)
    for (int x = 0; x < s.image.width; ++x)
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) {
          const tessera::Ray r = cam.generate(x + (sx + 0.5) / 4, y + (sy + 0.5) / 4, 0.5, 0.5);
          sum += std::exp(-tau_z / r.d.z);
          ++n;
        }
  return sum / n;
}

/// A purely absorbing medium (albedo 0) with opacity = u over a constant background 1.
tessera::SceneDesc absorber(const tessera::VolumeGeometry& g, double lo, double hi, double density) {
  tessera::SceneDesc s;
  s.geometry = g;
  s.tf.lo = lo;
  s.tf.hi = hi;
  s.tf.density_scale = density;
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.0));
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(1.0);
  s.integrator.shading = tessera::Shading::Phase;
  s.integrator.macrocell = 2;
  s.image = {16, 16, 128, 0.0};
  s.options.seed = 4242;
  return s;
}

/// Renders and z-tests the image mean against T.
void check_transmittance(const FieldView& view, tessera::SceneDesc s, double tau_z) {
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  frame_box(s, ps.bounds());
  const double T = expected_transmittance(s, tau_z);
  const tessera::PreparedScene framed = tessera::prepare(view, s);
  tessera::RenderStats st;
  const tessera::Film film = tessera_test::render_film(framed, &st);
  const auto L = tessera_test::luminance_stats(film);
  INFO("expected T " << T << " (tau " << tau_z << "), got " << L.mean << " +- " << L.se);
  CHECK(L.se > 0.0);
  CHECK(L.z(T) < 4.0);
  CHECK(st.discarded_samples == 0);
}

/// A scattering scene lit by the background and a sphere light, over the bounds b.
tessera::SceneDesc scattering_scene(const tessera::VolumeGeometry& g, const tessera::Bounds& b, double lo, double hi) {
  tessera::SceneDesc s;
  s.geometry = g;
  s.tf.lo = lo;
  s.tf.hi = hi;
  s.tf.density_scale = 4.0 / (b.hi.z - b.lo.z);
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.1, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.8, 0.7, 0.6));
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(0.5);
  s.lights.push_back(tessera::SphereLightDesc{b.hi + Vec3(1.0), 0.3, Color(20.0)});
  s.camera.position = b.center() + Vec3(0.3, 0.8, -3.0) * glm::length(b.hi - b.lo);
  s.camera.look_at = b.center();
  s.camera.fov_deg = 30.0;
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 8;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.macrocell = 2;
  s.image = {20, 20, 48, 0.0};
  return s;
}

double z_difference(const tessera_test::MeanWithError& a, const tessera_test::MeanWithError& b) {
  return std::fabs(a.mean - b.mean) / std::sqrt(a.se * a.se + b.se * b.se);
}

std::vector<float> random_field(tessera::Rng& rng, std::int64_t nx, std::int64_t ny, std::int64_t nz) {
  std::vector<float> f(static_cast<std::size_t>(nx * ny * nz));
  for (float& v : f) v = static_cast<float>(rng.uniform());
  return f;
}

}  // namespace

TEST_CASE("cell data is the clamped trilinear field of its centres over the whole cells' box", "[cell][medium]") {
  tessera::Rng rng(11, 0, 0, 0);
  const std::int64_t n[3] = {6, 5, 7};
  const std::vector<float> field = random_field(rng, n[0], n[1], n[2]);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n[0], n[1], n[2]);
  tessera::VolumeGeometry cell{Vec3(-1.0, 0.5, 2.0), Vec3(0.3, 0.2, 0.25), Association::Cell};
  tessera::VolumeGeometry vertex = cell;
  vertex.association = Association::Vertex;
  for (int a = 0; a < 3; ++a) vertex.origin[a] = cell.origin[a] + 0.5 * cell.spacing[a];
  tessera::SceneDesc s;
  s.tf.density_scale = 3.0;
  s.camera.position = Vec3(0.0, 0.0, -5.0);
  s.geometry = cell;
  const tessera::PreparedScene pc = tessera::prepare(view, s);
  s.geometry = vertex;
  const tessera::PreparedScene pv = tessera::prepare(view, s);
  // Bounds: the cells' box, and the centres' box
  for (int a = 0; a < 3; ++a) {
    CHECK(pc.bounds().lo[a] == cell.origin[a]);
    CHECK(pc.bounds().hi[a] == cell.origin[a] + static_cast<double>(n[a]) * cell.spacing[a]);
    CHECK(pv.bounds().lo[a] == vertex.origin[a]);
  }
  const tessera::KernelScene& kc = tessera::prepared_scene_impl(pc).kernel;
  const tessera::KernelScene& kv = tessera::prepared_scene_impl(pv).kernel;
  const auto mc = tessera::make_medium<float>(kc);
  const auto mv = tessera::make_medium<float>(kv);
  CHECK(mc.outer_half);
  CHECK_FALSE(mv.outer_half);
  // The same p space: p = (x - centre 0) / spacing
  for (int a = 0; a < 3; ++a) {
    CHECK(kc.origin[a] == kv.origin[a]);
    CHECK(kc.inv_spacing[a] == kv.inv_spacing[a]);
  }
  // Every point of the cells' box (the outer half cell included: the vertex medium clamps
  // there, as cell data must) has the same value, bit for bit
  int same = 0, half_cell = 0;
  for (int i = 0; i < 4000; ++i) {
    Vec3 x;
    for (int a = 0; a < 3; ++a) x[a] = pc.bounds().lo[a] + (pc.bounds().hi[a] - pc.bounds().lo[a]) * rng.uniform();
    if (i < 8)
      for (int a = 0; a < 3; ++a) x[a] = (i >> a) & 1 ? pc.bounds().hi[a] : pc.bounds().lo[a];  // the corners
    const Vec3 p = (x - kc.origin) * kc.inv_spacing;
    same += mc.value(p) == mv.value(p) ? 1 : 0;
    bool outside = false;
    for (int a = 0; a < 3; ++a) outside = outside || x[a] < pv.bounds().lo[a] || x[a] > pv.bounds().hi[a];
    half_cell += outside ? 1 : 0;
  }
  CHECK(same == 4000);
  CHECK(half_cell > 1000);
  // The corner of the cells' box holds the corner centre's value
  CHECK(mc.value((pc.bounds().lo - kc.origin) * kc.inv_spacing) == static_cast<double>(field[0]));
}

TEST_CASE("cell data: Beer-Lambert through the whole cells' box, outer half cells at the clamped value",
          "[cell][transmittance][render]") {
  // Values v_k = k + 1 on layers k along z (n_z cells of height h): the optical depth through
  // the cells' box is s h (v_0 / 2 + sum_k (v_k + v_k+1) / 2 + v_last / 2), the first and
  // last terms being the two outer half cells at their clamped values.
  constexpr std::int64_t nx = 4, ny = 4, nz = 6;
  std::vector<float> field(static_cast<std::size_t>(nx * ny * nz));
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        field[static_cast<std::size_t>((k * ny + j) * nx + i)] = static_cast<float>(k + 1);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, nx, ny, nz);
  const double h = 0.5, s_scale = 0.3;
  const tessera::VolumeGeometry g{Vec3(1.0, -2.0, 0.25), Vec3(0.7, 0.6, h), Association::Cell};
  double integral = 0.5 * 1.0 + 0.5 * static_cast<double>(nz);  // the two half cells
  for (std::int64_t k = 0; k + 1 < nz; ++k) integral += 0.5 * static_cast<double>((k + 1) + (k + 2));
  // Opacity u = v / hi, hi = nz: sigma = s v / nz
  const double tau = s_scale * h * integral / static_cast<double>(nz);
  for (const auto mode : {tessera::MajorantMode::Grid, tessera::MajorantMode::Global}) {
    tessera::SceneDesc s = absorber(g, 0.0, static_cast<double>(nz), s_scale);
    s.integrator.majorant = mode;
    check_transmittance(view, s, tau);
  }
  SECTION("constant cells: exp(-sigma n h) over the cells' box, not the centres'") {
    const std::vector<float> ones(static_cast<std::size_t>(nx * ny * nz), 1.0f);
    const FieldView v1 = FieldView::contiguous(ones.data(), tessera::DType::Float32, nx, ny, nz);
    tessera::SceneDesc s = absorber(g, 0.0, 1.0, 0.4);
    check_transmittance(v1, s, 0.4 * h * static_cast<double>(nz));
  }
}

TEST_CASE("cell data renders as the vertex field at its centres when the outer half cells are empty",
          "[cell][render]") {
  // Statistically the same, not bit-identical: the cell medium's box is half a cell larger,
  // so the box clip (and with it the first exponential step of every ray) differs, though
  // the extinction is the same function of position everywhere (0 in the outer half cell,
  // where the boundary centres are 0).
  constexpr std::int64_t n = 10;
  std::vector<float> field(static_cast<std::size_t>(n * n * n), 0.0f);
  for (std::int64_t k = 1; k + 1 < n; ++k)
    for (std::int64_t j = 1; j + 1 < n; ++j)
      for (std::int64_t i = 1; i + 1 < n; ++i) {
        const double x = (i - 4.5) / 4.0, y = (j - 4.5) / 4.0, z = (k - 4.5) / 4.0;
        field[static_cast<std::size_t>((k * n + j) * n + i)] =
            static_cast<float>(std::exp(-2.0 * (x * x + y * y + z * z)));
      }
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);
  const tessera::VolumeGeometry cell{Vec3(0.0), Vec3(0.1), Association::Cell};
  tessera::VolumeGeometry vertex{Vec3(0.05), Vec3(0.1), Association::Vertex};
  const tessera::Bounds b{Vec3(0.0), Vec3(1.0)};
  tessera::SceneDesc s = scattering_scene(cell, b, 0.0, 1.0);
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});  // 0 where the value is 0
  s.options.seed = 1;
  const auto Lc = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(view, s)));
  s.geometry = vertex;
  s.options.seed = 2;
  const auto Lv = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(view, s)));
  INFO("cell " << Lc.mean << " +- " << Lc.se << ", vertex " << Lv.mean << " +- " << Lv.se);
  CHECK(Lc.se > 0.0);
  CHECK(z_difference(Lc, Lv) < 4.0);
}

TEST_CASE("a linear field on stretched rectilinear axes renders as on a uniform grid", "[rectilinear][render]") {
  // v = x + 2 y + 3 z is reproduced exactly by trilinear interpolation on any grid, so both
  // media have the same extinction everywhere and the same gradients: two independent
  // renders (own seeds) z-tested against each other. x and z are rectilinear, y uniform.
  constexpr int nx = 9, ny = 8, nz = 12;
  const std::vector<double> cx = stretched(nx, 0.0, 1.0, 1.3), cz = stretched(nz, 0.0, 1.5, 0.8);
  const double hy = 1.2 / (ny - 1);
  auto fill = [&](const std::vector<double>& xs, const std::vector<double>& zs) {
    std::vector<double> f(static_cast<std::size_t>(nx * ny * nz));
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          f[static_cast<std::size_t>((k * ny + j) * nx + i)] =
              xs[static_cast<std::size_t>(i)] + 2.0 * j * hy + 3.0 * zs[static_cast<std::size_t>(k)];
    return f;
  };
  std::vector<double> ux(nx), uz(nz);
  for (int i = 0; i < nx; ++i) ux[static_cast<std::size_t>(i)] = 1.0 * i / (nx - 1);
  for (int k = 0; k < nz; ++k) uz[static_cast<std::size_t>(k)] = 1.5 * k / (nz - 1);
  const std::vector<double> fr = fill(cx, cz), fu = fill(ux, uz);
  const FieldView vr = FieldView::contiguous(fr.data(), tessera::DType::Float64, nx, ny, nz);
  const FieldView vu = FieldView::contiguous(fu.data(), tessera::DType::Float64, nx, ny, nz);
  tessera::VolumeGeometry gr{Vec3(0.0), Vec3(1.0, hy, 1.0)};
  gr.coords[0] = cx.data();
  gr.coords[2] = cz.data();
  const tessera::VolumeGeometry gu{Vec3(0.0), Vec3(1.0 / (nx - 1), hy, 1.5 / (nz - 1))};
  const tessera::Bounds b{Vec3(0.0), Vec3(1.0, 1.2, 1.5)};
  // Shading by the BRDF at every collision: the normal is the world gradient's direction,
  // the same on both grids (hybrid shading's choice depends on the gradient per sample
  // interval, which differs between grids by design)
  for (const auto shadow : {tessera::ShadowMode::Ratio, tessera::ShadowMode::Delta}) {
    tessera::SceneDesc s = scattering_scene(gr, b, 0.0, 1.0 + 2.4 + 4.5);
    s.integrator.shading = tessera::Shading::Brdf;
    s.integrator.shadow = shadow;
    s.options.seed = 5;
    const tessera::PreparedScene pr = tessera::prepare(vr, s);
    for (int a = 0; a < 3; ++a) {
      CHECK(pr.bounds().lo[a] == b.lo[a]);
      CHECK(pr.bounds().hi[a] == Approx(b.hi[a]));
    }
    const auto Lr = tessera_test::luminance_stats(tessera_test::render_film(pr));
    s.geometry = gu;
    s.options.seed = 6;
    const auto Lu = tessera_test::luminance_stats(tessera_test::render_film(tessera::prepare(vu, s)));
    INFO((shadow == tessera::ShadowMode::Delta ? "delta" : "ratio")
         << ": rectilinear " << Lr.mean << " +- " << Lr.se << ", uniform " << Lu.mean << " +- " << Lu.se);
    CHECK(Lr.se > 0.0);
    CHECK(z_difference(Lr, Lu) < 4.0);
  }
}

TEST_CASE("transmittance along a rectilinear axis: exp(-integral of the linear field)",
          "[rectilinear][transmittance][render]") {
  // v = z on a stretched z axis over [0, D], opacity u = v / D: sigma = s z / D, so the
  // optical depth along z is s D / 2 (vertex data). Cell data with the centres' z as values
  // adds the outer half cells at the clamped values m_0 and m_last.
  constexpr int nx = 4, ny = 4, nz = 10;
  const double D = 2.0, s_scale = 1.5;
  const std::vector<double> xs = stretched(nx, -0.5, 0.5, 2.0), ys = stretched(ny, 0.0, 0.8, 0.5);
  SECTION("vertex data") {
    const std::vector<double> zs = stretched(nz, 0.0, D, 1.25);
    std::vector<float> f(static_cast<std::size_t>(nx * ny * nz));
    for (int k = 0; k < nz; ++k)
      for (int i = 0; i < nx * ny; ++i)
        f[static_cast<std::size_t>(k * nx * ny + i)] = static_cast<float>(zs[static_cast<std::size_t>(k)]);
    const FieldView view = FieldView::contiguous(f.data(), tessera::DType::Float32, nx, ny, nz);
    tessera::VolumeGeometry g;
    g.coords[0] = xs.data();
    g.coords[1] = ys.data();
    g.coords[2] = zs.data();
    for (const auto mode : {tessera::MajorantMode::Grid, tessera::MajorantMode::Global}) {
      tessera::SceneDesc s = absorber(g, 0.0, D, s_scale);
      s.integrator.majorant = mode;
      // float values: the field holds z rounded to float, a relative 6e-8, far below the noise
      check_transmittance(view, s, s_scale * D / 2.0);
    }
  }
  SECTION("cell data") {
    const std::vector<double> zb = stretched(nz + 1, 0.0, D, 1.25);
    std::vector<double> f(static_cast<std::size_t>(nx * ny * nz));
    std::vector<double> xb = stretched(nx + 1, -0.5, 0.5, 2.0), yb = stretched(ny + 1, 0.0, 0.8, 0.5);
    for (int k = 0; k < nz; ++k)
      for (int i = 0; i < nx * ny; ++i)
        f[static_cast<std::size_t>(k * nx * ny + i)] =
            0.5 * (zb[static_cast<std::size_t>(k)] + zb[static_cast<std::size_t>(k) + 1]);
    const FieldView view = FieldView::contiguous(f.data(), tessera::DType::Float64, nx, ny, nz);
    tessera::VolumeGeometry g{Vec3(0.0), Vec3(1.0), Association::Cell};
    g.coords[0] = xb.data();
    g.coords[1] = yb.data();
    g.coords[2] = zb.data();
    const double m0 = f.front(), m1 = f.back();
    const double integral = (m1 * m1 - m0 * m0) / 2.0 + (m0 - 0.0) * m0 + (D - m1) * m1;
    tessera::SceneDesc s = absorber(g, 0.0, D, s_scale);
    check_transmittance(view, s, s_scale * integral / D);
  }
}

TEST_CASE("majorants bound the extinction along the walk under rectilinear axes and cell data",
          "[majorant][rectilinear][cell]") {
  tessera::Rng rng(2024, 0, 0, 0);
  int bad = 0, segments = 0, rectilinear_trials = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const bool cell = trial % 2 == 1;
    std::int64_t n[3];
    for (int a = 0; a < 3; ++a) n[a] = 1 + static_cast<std::int64_t>(rng.uniform() * 13.0);
    if (trial % 5 == 2) n[trial % 3] = 2;
    const std::vector<float> field = random_field(rng, n[0], n[1], n[2]);
    const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n[0], n[1], n[2]);
    tessera::VolumeGeometry g{Vec3(-0.3, 0.2, 1.0), Vec3(0.2, 0.35, 0.1),
                              cell ? Association::Cell : Association::Vertex};
    std::vector<double> coords[3];
    for (int a = 0; a < 3; ++a) {
      if ((trial >> (a % 2)) % 3 == 0 && a != 1) continue;  // some axes stay uniform
      const int count = static_cast<int>(n[a] + (cell ? 1 : 0));
      if (count < 2) continue;
      coords[a] = stretched(count, -1.0 + a, 1.0 + a + rng.uniform(), 0.6 + 1.2 * rng.uniform());
      g.coords[a] = coords[a].data();
    }
    tessera::SceneDesc s;
    s.geometry = g;
    s.tf.density_scale = 0.5 + 20.0 * rng.uniform();
    s.tf.opacity =
        tessera::ScalarTF({0.0, 0.3, 0.6, 1.0}, {rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()});
    s.camera.position = Vec3(0.0, 0.0, -10.0);
    s.integrator.majorant = tessera::MajorantMode::Grid;
    s.integrator.macrocell = 1 + trial % 4;
    const tessera::PreparedScene ps = tessera::prepare(view, s);
    const tessera::KernelScene& ks = tessera::prepared_scene_impl(ps).kernel;
    // The kernels' Value: Rectilinear<float> when some axis is rectilinear (kernel_dispatch.h)
    tessera::with_value(ks, [&](auto tag) {
      using V = typename decltype(tag)::type;
      if constexpr (tessera::GridMedium<V>::kRectilinear) ++rectilinear_trials;
      tessera_test::walk_rays(tessera::make_medium<V>(ks), cell, rng, bad, segments);
    });
  }
  CHECK(rectilinear_trials > 10);
  CHECK(segments > 1000);
  CHECK(bad == 0);
}

TEST_CASE("cell data on rectilinear axes: bit-identical across threads and tile sizes",
          "[cell][rectilinear][determinism]") {
  tessera::Rng rng(3, 0, 0, 0);
  constexpr std::int64_t nx = 12, ny = 9, nz = 10;
  const std::vector<float> field = random_field(rng, nx, ny, nz);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, nx, ny, nz);
  const std::vector<double> xb = stretched(nx + 1, 0.0, 1.0, 1.2), zb = stretched(nz + 1, -0.5, 0.7, 0.85);
  tessera::VolumeGeometry g{Vec3(0.0, 0.1, 0.0), Vec3(1.0, 0.1, 1.0), Association::Cell};
  g.coords[0] = xb.data();
  g.coords[2] = zb.data();
  const tessera::Bounds b{Vec3(0.0, 0.1, -0.5), Vec3(1.0, 1.0, 0.7)};
  tessera::SceneDesc s = scattering_scene(g, b, 0.0, 1.0);
  s.image = {21, 17, 6, 0.0};
  s.options.seed = 9;
  std::vector<tessera::PixelSums> ref;
  for (const int threads : {1, 3})
    for (const int tile : {8, 0, 5}) {
      s.options.threads = threads;
      s.options.tile = tile;
      const auto px = tessera_test::render_film(tessera::prepare(view, s)).pixels();
      if (ref.empty()) {
        ref = px;
        continue;
      }
      INFO("threads " << threads << ", tile " << tile);
      REQUIRE(px.size() == ref.size());
      CHECK(std::memcmp(px.data(), ref.data(), px.size() * sizeof(tessera::PixelSums)) == 0);
    }
}
