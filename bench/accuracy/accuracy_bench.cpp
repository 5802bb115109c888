// Accuracy benchmark: the longer versions of the accuracy suite's references
// (docs/accuracy.md), printed and written as CSV. Not a test: it asserts nothing.
//
//   accuracy_bench [OUT_DIR] [--quick]      (default OUT_DIR: bench/results)
//
// Writes OUT_DIR/accuracy_furnace.csv      white furnace, tau 0.01..100 x g -0.7, 0, 0.7
//       OUT_DIR/accuracy_convergence.csv  RMSE vs spp (4..4096) against a 65536-spp reference
//       OUT_DIR/accuracy_raymarch.csv     ray-march bias vs step: deterministic model and the
//                                         renderer's measured transmittance and radiance bias
// --quick divides every sample count by 16 (a smoke run).
#include "accuracy_support.h"
#include "raymarch_model.h"
#include "reference_scenes.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

using namespace tessera_acc;

namespace {

int g_div = 1;  // --quick: 16

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---------------------------------------------------------------------------------------------
// White furnace
// ---------------------------------------------------------------------------------------------
void furnace(const std::string& dir) {
  std::printf("\n== White furnace: albedo 1, background L = 0.6, 16 x 16 pixels ==\n");
  std::printf("%8s %6s %6s %10s %10s %7s %9s %5s %9s %8s %8s\n", "tau", "g", "spp", "mean", "se", "|z|", "chi2", "dof",
              "crit", "coll/smp", "seconds");
  std::ofstream csv(dir + "/accuracy_furnace.csv");
  csv << "tau,g,spp,mean,se,abs_z,chi2,dof,chi2_critical,max_abs_z,z_critical,collisions_per_sample,seconds\n";
  const std::vector<float> field = constant_field(5, 5, 5, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 5, 5, 5);
  constexpr double kL = 0.6;
  for (const double tau : {0.01, 1.0, 10.0, 100.0}) {
    for (const double g : {-0.7, 0.0, 0.7}) {
      tessera::SceneDesc s = furnace_scene(tau, g, kL);
      const int spp = std::max(4, (tau < 5.0 ? 4096 : tau < 50.0 ? 2048 : 512) / g_div);
      s.image = {16, 16, spp, 0.0};
      s.options.seed = 17;
      const auto t0 = std::chrono::steady_clock::now();
      tessera::RenderStats st;
      const tessera::Film film = render(view, s, &st);
      const double secs = seconds_since(t0);
      const PixelTest t = compare_to_expected(film, std::vector<double>(256, kL));
      const ImageMean m = image_mean(film);
      const double cps = static_cast<double>(st.real_collisions) / st.samples;
      std::printf("%8.2f %6.2f %6d %10.6f %10.2e %7.2f %9.1f %5d %9.1f %8.1f %8.2f\n", tau, g, spp, m.mean, m.se,
                  m.z(kL), t.chi2, t.dof, t.chi2_crit, cps, secs);
      csv << tau << "," << g << "," << spp << "," << m.mean << "," << m.se << "," << m.z(kL) << "," << t.chi2 << ","
          << t.dof << "," << t.chi2_crit << "," << t.max_abs_z << "," << t.z_crit << "," << cps << "," << secs << "\n";
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Convergence
// ---------------------------------------------------------------------------------------------
void convergence(const std::string& dir) {
  std::printf("\n== Convergence: RMSE vs spp against an independent 65536-spp reference ==\n");
  constexpr int kN = 17;
  const std::vector<float> field = cloud_field(kN, kN, kN);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::SceneDesc s = convergence_scene(kN);
  s.image = {16, 16, 65536 / g_div, 0.0};
  s.options.seed = 800;
  auto t0 = std::chrono::steady_clock::now();
  const PixelMoments ref = pixel_moments(render(view, s));
  std::printf("reference: %d spp in %.1f s\n", s.image.spp, seconds_since(t0));
  double ref_var = 0.0, px_var = 0.0;
  for (std::size_t i = 0; i < ref.var_mean.size(); ++i) {
    ref_var += ref.var_mean[i];
    px_var += ref.var_mean[i] * static_cast<double>(ref.n[i]);  // per-sample variance
  }
  ref_var /= ref.var_mean.size();
  px_var /= ref.var_mean.size();

  s.image.spp = 4;
  s.options.seed = 801;
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  tessera::Film film(16, 16);
  tessera::RenderStats st;
  std::ofstream csv(dir + "/accuracy_convergence.csv");
  csv << "spp,rmse,rmse_predicted,seconds\n";
  std::printf("%6s %12s %14s %8s\n", "spp", "RMSE", "sigma/sqrt(N)", "seconds");
  std::vector<double> lx, ly;
  int n = 0;
  t0 = std::chrono::steady_clock::now();
  for (int target = 4; target <= 4096; target *= 2) {
    while (n < target) {
      tessera::render(ps, film, st);
      n += 4;
    }
    const double mse = mse_vs_reference(pixel_moments(film), ref, ref_var);
    const double rmse = std::sqrt(std::max(mse, 0.0)), pred = std::sqrt(px_var / n);
    std::printf("%6d %12.6f %14.6f %8.2f\n", n, rmse, pred, seconds_since(t0));
    csv << n << "," << rmse << "," << pred << "," << seconds_since(t0) << "\n";
    if (mse > 0.0) {
      lx.push_back(std::log(static_cast<double>(n)));
      ly.push_back(0.5 * std::log(mse));
    }
  }
  std::printf("log-log slope of RMSE over 4..%d spp: %.4f (expected -0.5)\n", n, least_squares_slope(lx, ly));
}

// ---------------------------------------------------------------------------------------------
// Ray-march bias
// ---------------------------------------------------------------------------------------------
void raymarch(const std::string& dir) {
  std::printf("\n== Ray-march bias vs step (smooth field, 17^3 vertices, optical depth ~2) ==\n");
  constexpr int kN = 17;
  const TrilinearField m = raymarch_field(kN, 3.5);
  const FieldView view = FieldView::contiguous(m.v.data(), tessera::DType::Float32, kN, kN, kN);
  tessera::SceneDesc s = raymarch_scene(kN, 3.5);
  std::ofstream csv(dir + "/accuracy_raymarch.csv");
  csv << "quantity,step_voxels,bias,se\n";

  // (1) Deterministic model over 32 x 32 rays.
  std::printf("(1) model: mean over 32 x 32 rays of E_xi[exp(-S)] - exp(-tau)\n");
  std::printf("%10s %14s %12s\n", "step", "bias", "local order");
  const RefCamera cam(s.camera, 32, 32);
  double prev = 0.0;
  std::vector<double> lx, ly;
  for (double step = 8.0; step >= 0.0625; step *= 0.5) {
    const double h = step / (kN - 1);
    double bias = 0.0;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        const Ray r = cam.ray(x + 0.5, y + 0.5);
        bias += raymarch_transmittance(m, r, h, 64) - exact_transmittance(m, r);
      }
    bias /= 1024.0;
    if (prev > 0.0) std::printf("%10.4f %14.6e %12.3f\n", step, bias, std::log2(prev / bias));
    else std::printf("%10.4f %14.6e %12s\n", step, bias, "-");
    csv << "transmittance_model," << step << "," << bias << ",0\n";
    if (step <= 1.0) {
      lx.push_back(std::log(step));
      ly.push_back(std::log(bias));
    }
    prev = bias;
  }
  std::printf("fitted order over steps <= 1 voxel: %.3f (expected 2)\n", least_squares_slope(lx, ly));

  // (2) The renderer: mean transmittance image of the march minus the exact one.
  std::printf("(2) renderer, transmittance: image mean of the march - exact (16 x 16 pixels)\n");
  std::printf("%10s %8s %14s %12s %8s\n", "step", "spp", "bias", "se", "bias/se");
  const std::vector<double> exact = expected_image(s, 2, [&](const Ray& r) { return exact_transmittance(m, r); });
  double exact_mean = 0.0;
  for (double v : exact) exact_mean += v;
  exact_mean /= exact.size();
  lx.clear();
  ly.clear();
  for (const double step : {8.0, 4.0, 2.0, 1.0}) {
    tessera::SceneDesc d = s;
    d.integrator.free_path = tessera::FreePath::Raymarch;
    d.integrator.step = step;
    d.image = {16, 16, 65536 / g_div, 0.0};
    d.options.seed = 2000 + static_cast<int>(step * 8);
    const ImageMean im = image_mean(render(view, d));
    const double bias = im.mean - exact_mean;
    std::printf("%10.4f %8d %14.6e %12.2e %8.1f\n", step, d.image.spp, bias, im.se, bias / im.se);
    csv << "transmittance_renderer," << step << "," << bias << "," << im.se << "\n";
    if (bias > 4.0 * im.se) {
      lx.push_back(std::log(step));
      ly.push_back(std::log(bias));
    }
  }
  if (lx.size() >= 2) std::printf("fitted order (points with bias > 4 se): %.3f\n", least_squares_slope(lx, ly));

  // (3) Radiance: a single-scattering cloud lit by a rect light, march vs delta tracking.
  std::printf("(3) renderer, radiance: single scattering, albedo 0.9, rect light; march - delta\n");
  std::printf("%10s %8s %14s %12s %8s\n", "step", "spp", "difference", "se", "diff/se");
  tessera::SceneDesc r = s;
  r.tf.diffuse = tessera::ColorTF::constant(Color(0.9));
  r.background.color = Color(0.0);
  r.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 1.6, 0.5), Vec3(0.5, 0.0, 0.5), 0.7, 0.7, Color(6.0)});
  r.image = {16, 16, 65536 / g_div, 0.0};
  r.options.seed = 3000;
  const ImageMean delta = image_mean(render(view, r));
  lx.clear();
  ly.clear();
  for (const double step : {8.0, 4.0, 2.0, 1.0, 0.5}) {
    tessera::SceneDesc d = r;
    d.integrator.free_path = tessera::FreePath::Raymarch;
    d.integrator.step = step;
    d.options.seed = 3001 + static_cast<int>(step * 8);
    const ImageMean im = image_mean(render(view, d));
    const double diff = im.mean - delta.mean, se = std::hypot(im.se, delta.se);
    std::printf("%10.4f %8d %14.6e %12.2e %8.1f\n", step, d.image.spp, diff, se, diff / se);
    csv << "radiance_renderer," << step << "," << diff << "," << se << "\n";
    if (std::fabs(diff) > 4.0 * se) {
      lx.push_back(std::log(step));
      ly.push_back(std::log(std::fabs(diff)));
    }
  }
  if (lx.size() >= 2)
    std::printf("fitted order (points with |difference| > 4 se): %.3f\n", least_squares_slope(lx, ly));
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress shows line by line when redirected
  std::string dir = "bench/results";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") g_div = 16;
    else if (a == "-h" || a == "--help") {
      std::printf("usage: accuracy_bench [OUT_DIR] [--quick]\n");
      return 0;
    } else dir = a;
  }
  std::filesystem::create_directories(dir);
  const auto t0 = std::chrono::steady_clock::now();
  furnace(dir);
  convergence(dir);
  raymarch(dir);
  std::printf("\nwrote %s/accuracy_{furnace,convergence,raymarch}.csv in %.1f s\n", dir.c_str(), seconds_since(t0));
  return 0;
}
