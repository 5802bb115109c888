// Reference (d): single scattering of a constant background in a homogeneous slab
// (docs/accuracy.md, "Single scattering").
//
// Geometry: a box 200 x 200 wide and D = 1 thick (a slab; sideways escape needs a path of
// >= 99 units, weight e^{-99 sigma}), seen at normal incidence by a 1-degree camera. Albedo a,
// HG asymmetry g, constant background L hidden from camera rays (visible: false), so a pixel
// holds only light scattered once:
//   L_ss = a L integral_0^D sigma e^{-sigma z} I(z) dz,
//   I(z) = integral over the sphere of p(cos) e^{-sigma l(z, w)} dw,
// l the distance to the slab's faces along w. With mu = |cos| to the slab normal, the z
// integral is elementary and
//   L_ss = 2 pi a L integral_0^1 mu [ p(mu) (e^{-tau} - e^{-tau/mu}) / (1 - mu)
//                                   + p(-mu) (1 - e^{-tau (1 + mu)/mu}) / (1 + mu) ] dmu,
// tau = sigma D (forward and backward scattering); evaluated by 200-point Gauss-Legendre.
// Thin limit: L_ss = a L tau (1 + O(tau log tau)). For g = 0 the backward half equals the
// classical (1/2) [1 - ln 2 - e^{-tau} (E2(tau) - E1(tau)) - E1(2 tau)], checked here too.
// Pixel rays deviate from the normal by < 0.71 degrees: an O(theta^2) < 2e-4 relative effect.
//
// Test: per-pixel chi-square and Bonferroni max |z| (alpha = 1e-4) with the film's sample
// variance, image mean |z| < 4; and the reference differs from the estimator that forgets the
// exit transmittance, a L (1 - e^{-tau}), by > 6 standard errors (the test has power).
#include <catch2/catch.hpp>

#include "accuracy_support.h"

#include <cmath>

using namespace tessera_acc;

namespace {

/// Single-scattered radiance at normal incidence, the formula above (a = L = 1).
double slab_single_scatter(double tau, double g) {
  static const GaussLegendre gl(200);
  return 2.0 * kPi * gl.integrate(0.0, 1.0, [&](double mu) {
    const double fwd = -std::exp(-tau) * std::expm1(-tau * (1.0 - mu) / mu) / (1.0 - mu);
    const double bwd = -std::expm1(-tau * (1.0 + mu) / mu) / (1.0 + mu);
    return mu * (hg(mu, g) * fwd + hg(-mu, g) * bwd);
  });
}

double E1(double x) { return -std::expint(-x); }
double E2(double x) { return std::exp(-x) - x * E1(x); }

}  // namespace

TEST_CASE("single-scattering slab formula: thin limit and the E_n closed form for g = 0",
          "[accuracy][single_scattering]") {
  // Thin limit: L_ss / tau -> 1 (a = L = 1) for any g.
  for (const double g : {-0.5, 0.0, 0.7}) CHECK(slab_single_scatter(1e-6, g) / 1e-6 == Approx(1.0).epsilon(1e-4));
  // Backward half for g = 0 against the exponential-integral form.
  static const GaussLegendre gl(200);
  for (const double tau : {0.1, 1.0, 3.0}) {
    const double quad =
        0.5 * gl.integrate(0.0, 1.0, [&](double mu) { return -mu * std::expm1(-tau * (1.0 + mu) / mu) / (1.0 + mu); });
    const double closed = 0.5 * (1.0 - std::log(2.0) - std::exp(-tau) * (E2(tau) - E1(tau)) - E1(2.0 * tau));
    INFO("tau " << tau);
    CHECK(quad == Approx(closed).epsilon(1e-10));
  }
}

TEST_CASE("single scattering of a constant background in a thin slab, per pixel", "[accuracy][single_scattering]") {
  constexpr double kAlbedo = 0.8, kL = 1.0;
  const std::vector<float> field = constant_field(2, 2, 2, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 2, 2, 2);
  for (const double tau : {0.1, 1.0}) {
    for (const double g : {0.0, 0.7, -0.5}) {
      SECTION("tau " + std::to_string(tau) + ", g " + std::to_string(g)) {
        tessera::SceneDesc s = unit_box_scene(tau, kAlbedo);
        s.geometry.origin = Vec3(-100.0, -100.0, 0.0);
        s.geometry.spacing = Vec3(200.0, 200.0, 1.0);
        s.integrator.phase_g = g;
        s.background.color = Color(kL);
        s.background.visible = false;
        s.camera.position = Vec3(0.03, -0.02, -10.0);
        s.camera.look_at = Vec3(0.03, -0.02, 0.5);
        s.camera.fov_deg = 1.0;
        s.image = {8, 8, 4096, 0.0};
        s.options.seed = 404;
        const double ref = kAlbedo * kL * slab_single_scatter(tau, g);
        const tessera::Film film = render(view, s);
        const std::vector<double> expected(64, ref);
        const PixelTest t = compare_to_expected(film, expected);
        const ImageMean m = image_mean(film);
        const double no_exit_T = kAlbedo * kL * (1.0 - std::exp(-tau));
        INFO("reference " << ref << ", image mean " << m.mean << " +- " << m.se << ", without exit transmittance "
                          << no_exit_T << "; " << t.describe());
        CHECK(t.ok());
        CHECK(m.z(ref) < 4.0);
        CHECK(std::fabs(no_exit_T - ref) > 6.0 * m.se);
      }
    }
  }
}
