// Convergence (docs/accuracy.md, "Convergence"): the RMSE of an N-spp image against a
// high-spp reference falls as N^(-1/2).
//
// Scene: 16 x 16 pixels of a heterogeneous cloud, hybrid shading with specular, a rect light
// and a gradient background, single scattering. The reference is an independent render
// (different seed) at 4096 spp. One film accumulates 4, 16, 64, 256 and 1024 spp by repeated
// 4-spp render calls (so the sample-index continuation across calls is part of the test);
//   MSE(N) = mean over pixels of (m_N - m_ref)^2 - mean over pixels of Var(m_ref),
// the second term removing the reference's own noise (estimated from its sample variance;
// the two films are independent, so the cross term has mean zero). The least-squares slope of
// log RMSE against log N must be -0.5 +- 0.05.
#include <catch2/catch.hpp>

#include "accuracy_support.h"

using namespace tessera_acc;

namespace {

/// Least-squares slope of y against x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= x.size();
  my /= y.size();
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  return sxy / sxx;
}

}  // namespace

TEST_CASE("RMSE against a 4096-spp reference falls as N^-1/2 from 4 to 1024 spp",
          "[accuracy][convergence]") {
  constexpr int kN = 17;
  const std::vector<float> field = cloud_field(kN, kN, kN);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::SceneDesc s = unit_box_scene(20.0, 0.8);
  s.geometry.spacing = Vec3(1.0 / (kN - 1));
  s.tf.opacity = tessera::ScalarTF({0.0, 0.1, 0.6, 1.0}, {0.0, 0.2, 1.0, 1.0});
  s.tf.specular = tessera::ColorTF::constant(Color(0.04));
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.gradient_factor = 2.0;
  s.camera.position = Vec3(1.5, 1.2, -1.6);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 36.0;
  s.rect_lights.push_back({Vec3(0.5, 1.9, 0.3), Vec3(0.5, 0.0, 0.5), 0.8, 0.8, Color(5.0)});
  s.background.type = tessera::BackgroundType::Gradient;
  s.background.up = Vec3(0.0, 1.0, 0.0);
  s.image = {16, 16, 4096, 0.0};
  s.options.seed = 800;
  const PixelMoments ref = pixel_moments(render(view, s));

  s.image.spp = 4;
  s.options.seed = 801;
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  tessera::Film film(16, 16);
  tessera::RenderStats st;
  std::vector<double> log_n, log_rmse;
  double ref_var = 0.0;
  for (double v : ref.var_mean) ref_var += v;
  ref_var /= ref.var_mean.size();
  std::ostringstream table;
  int n = 0;
  for (const int target : {4, 16, 64, 256, 1024}) {
    while (n < target) {
      tessera::render(ps, film, st);
      n += 4;
    }
    const PixelMoments m = pixel_moments(film);
    double mse = 0.0;
    for (std::size_t i = 0; i < m.mean.size(); ++i) mse += (m.mean[i] - ref.mean[i]) * (m.mean[i] - ref.mean[i]);
    mse = mse / m.mean.size() - ref_var;
    REQUIRE(mse > 0.0);
    log_n.push_back(std::log(static_cast<double>(n)));
    log_rmse.push_back(0.5 * std::log(mse));
    table << "spp " << n << ": RMSE " << std::sqrt(mse) << "\n";
  }
  const double k = slope(log_n, log_rmse);
  INFO(table.str() << "slope " << k << ", reference noise (mean variance of its pixel means) " << ref_var);
  CHECK(st.discarded_samples == 0);
  CHECK(std::fabs(k + 0.5) < 0.05);
}
