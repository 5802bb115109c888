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
#include "reference_scenes.h"

using namespace tessera_acc;

TEST_CASE("RMSE against a 4096-spp reference falls as N^-1/2 from 4 to 1024 spp", "[accuracy][convergence]") {
  constexpr int kN = 17;
  const std::vector<float> field = cloud_field(kN, kN, kN);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::SceneDesc s = convergence_scene(kN);
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
    const double mse = mse_vs_reference(pixel_moments(film), ref, ref_var);
    REQUIRE(mse > 0.0);
    log_n.push_back(std::log(static_cast<double>(n)));
    log_rmse.push_back(0.5 * std::log(mse));
    table << "spp " << n << ": RMSE " << std::sqrt(mse) << "\n";
  }
  const double k = least_squares_slope(log_n, log_rmse);
  INFO(table.str() << "slope " << k << ", reference noise (mean variance of its pixel means) " << ref_var);
  CHECK(st.discarded_samples == 0);
  CHECK(std::fabs(k + 0.5) < 0.05);
}
