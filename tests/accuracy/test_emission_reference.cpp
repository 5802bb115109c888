// Reference (c): emission-only media (docs/accuracy.md, "Emission").
//
// Albedo 0, black background, no lights: emission is collected at real collisions (emission
// coefficient sigma_t Le), so a camera ray's expected radiance is
//   L = integral over the ray of sigma_t(t) Le(t) T(0, t) dt,
// which for a homogeneous box is Le (1 - T) with T = exp(-sigma_t chord). In the homogeneous
// case a sample is Le on a collision and 0 otherwise (exact binomial variance Le^2 T (1 - T));
// in the heterogeneous case (a linear field through piecewise-linear opacity and emission TFs)
// the ray integral is evaluated by Gauss-Legendre quadrature between the points where the TFs
// kink (the integrand is smooth there), and the film's sample variance is used.
//
// Test: per-pixel chi-square and Bonferroni max |z| at alpha = 1e-4 (homogeneous case: binomial
// counts, rare-outcome pixels pooled into exact Poisson tests, see accuracy_support.h); in the
// homogeneous case also sum(L) == Le * sum(A) exactly (every sample is (Le, 1) or (0, 0)).
#include <catch2/catch.hpp>

#include "accuracy_support.h"

using namespace tessera_acc;

TEST_CASE("emission-only homogeneous box: L = Le (1 - T) per pixel", "[accuracy][emission]") {
  constexpr double kLe = 2.0, kSigma = 1.5;
  const std::vector<float> field = constant_field(3, 3, 3, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 3, 3, 3);
  tessera::SceneDesc s = unit_box_scene(kSigma, 0.0);
  s.geometry.spacing = Vec3(0.5);
  s.tf.emission = tessera::ColorTF::constant(Color(kLe));
  s.camera.position = Vec3(2.1, 1.6, -1.7);
  s.camera.look_at = Vec3(0.5, 0.45, 0.55);
  s.camera.fov_deg = 40.0;
  s.image = {16, 16, 1024, 0.0};
  s.options.seed = 303;
  for (const auto sc : {tessera::Scattering::Single, tessera::Scattering::Multiple}) {
    SECTION(sc == tessera::Scattering::Single ? "single scattering" : "multiple scattering") {
      s.integrator.scattering = sc;
      const std::vector<double> T =
          expected_image(s, 64, [&](const Ray& r) { return std::exp(-kSigma * chord(r, Vec3(0.0), Vec3(1.0))); });
      std::vector<double> p_collide(T.size());
      for (std::size_t i = 0; i < T.size(); ++i) p_collide[i] = 1.0 - T[i];
      const tessera::Film film = render(view, s);
      const PixelTest t = compare_binomial(film, p_collide, kLe);
      bool exact_pairs = true;
      for (const tessera::PixelSums& p : film.pixels()) exact_pairs = exact_pairs && p.r == kLe * p.a;
      INFO(t.describe());
      CHECK(t.ok());
      CHECK(t.mean_z() < 4.0);
      CHECK(exact_pairs);
    }
  }
}

TEST_CASE("emission-only heterogeneous box: integral of sigma_t Le T along each ray", "[accuracy][emission]") {
  // v = (x + 2y + 3z) / 6 on the unit box (9^3 vertices): trilinear interpolation reproduces a
  // linear field, so u(t) is linear along every ray.
  constexpr int n = 9;
  std::vector<float> field(n * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        field[(k * n + j) * n + i] = static_cast<float>((i + 2.0 * j + 3.0 * k) / (6.0 * (n - 1)));
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n);

  const std::vector<double> op_x{0.0, 0.4, 1.0}, op_v{0.3, 1.0, 0.5};
  const std::vector<double> em_x{0.0, 0.5, 1.0}, em_v{0.2, 2.0, 1.0};
  const double scale = 2.5;
  tessera::SceneDesc s = unit_box_scene(scale, 0.0);
  s.geometry.spacing = Vec3(1.0 / (n - 1));
  s.tf.opacity = tessera::ScalarTF(op_x, op_v);
  s.tf.emission = tessera::ColorTF(em_x, {Color(em_v[0]), Color(em_v[1]), Color(em_v[2])});
  s.integrator.macrocell = 2;
  // Every camera ray enters through the face z = 0 (no silhouette in the image), so each
  // pixel's integrand is continuous and an 8 x 8 midpoint rule is accurate.
  s.camera.position = Vec3(0.5, 0.5, -1.5);
  s.camera.look_at = Vec3(0.5, 0.52, 0.5);
  s.camera.up = Vec3(0.0, 1.0, 0.0);
  s.camera.fov_deg = 24.0;
  s.image = {16, 16, 1024, 0.0};
  s.options.seed = 304;

  auto pwl = [](const std::vector<double>& xs, const std::vector<double>& vs, double u) {
    if (u <= xs.front()) return vs.front();
    if (u >= xs.back()) return vs.back();
    std::size_t i = 1;
    while (xs[i] < u) ++i;
    const double f = (u - xs[i - 1]) / (xs[i] - xs[i - 1]);
    return vs[i - 1] + f * (vs[i] - vs[i - 1]);
  };
  const GaussLegendre gl(16);
  auto ray_radiance = [&](const Ray& r) {
    double t0, t1;
    if (!box_interval(r, Vec3(0.0), Vec3(1.0), &t0, &t1)) return 0.0;
    auto u_at = [&](double t) {
      const Vec3 p = r.o + t * r.d;
      return std::clamp((p.x + 2.0 * p.y + 3.0 * p.z) / 6.0, 0.0, 1.0);
    };
    auto sigma = [&](double t) { return scale * pwl(op_x, op_v, u_at(t)); };
    // Pieces between the kinks u = 0.4 and u = 0.5 (u is linear in t).
    std::vector<double> cuts{t0, t1};
    const double ua = u_at(t0), ub = u_at(t1);
    for (const double k : {0.4, 0.5})
      if ((ua - k) * (ub - k) < 0.0) cuts.push_back(t0 + (k - ua) / (ub - ua) * (t1 - t0));
    std::sort(cuts.begin(), cuts.end());
    double L = 0.0, od = 0.0;  // od: optical depth up to the piece start (exact: sigma linear)
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double a = cuts[i], b = cuts[i + 1], sa = sigma(a);
      L += gl.integrate(a, b, [&](double t) {
        const double st = sigma(t);
        return st * pwl(em_x, em_v, u_at(t)) * std::exp(-(od + 0.5 * (sa + st) * (t - a)));
      });
      od += 0.5 * (sa + sigma(b)) * (b - a);
    }
    return L;
  };
  const std::vector<double> expected = expected_image(s, 8, ray_radiance);
  for (const auto mode : {tessera::MajorantMode::Grid, tessera::MajorantMode::Global}) {
    SECTION(mode == tessera::MajorantMode::Grid ? "grid majorant" : "global majorant") {
      s.integrator.majorant = mode;
      tessera::RenderStats st;
      const tessera::Film film = render(view, s, &st);
      const PixelTest t = compare_to_expected(film, expected);
      INFO(t.describe());
      CHECK(st.null_collisions > 0);  // heterogeneous: delta tracking rejects tentative events
      CHECK(t.ok());
      CHECK(t.mean_z() < 4.0);
    }
  }
}
