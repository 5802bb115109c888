// Refinement levels (amr.h), core only: render time and field lookups of a hierarchy against
// the uniform field at its finest resolution over the same extent. Not a test: prints the
// figures and writes CSV rows.
//
//   amr_bench [--csv FILE] [--grid N] [--image W H] [--spp S] [--reps R] [--threads T]
//             [--levels L] [--ratio R] [--macrocell E] [--haze H]
//
// The scene: cell data over the unit cube, a faint smooth haze everywhere and a sharp hot spot
// (a Gaussian of width 0.03) that only the finer levels resolve. Level 0 has N^3 cells; each
// finer level refines (by R) the cube of a quarter of the extent around the spot, the level
// above's region halved; every level samples the same function at its cells' centres. The
// uniform reference samples it at the finest level's resolution everywhere: N R^(L-1) cells
// per axis. Each variant renders `reps` times, interleaved; the fastest is kept.
//
// Defaults: amr_bench.csv, N = 48, L = 2, R = 2, 160x160, 16 spp, 3 reps, 1 thread, macrocell 8
// (for the hierarchy also 4: its macrocells are in level-0 cells).
#include <tessera/amr.h>
#include <tessera/render.h>

#include "bench_args.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

using tessera::Color;
using tessera::Vec3;

namespace {

using Clock = std::chrono::steady_clock;

struct Args : tessera::bench::BenchArgs {
  int levels = 2, ratio = 2, macrocell = 8;
  double haze = 0.08;  ///< the smooth background's amplitude; 0: empty space around the spot
};

Args parse(int argc, char** argv) {
  Args a;
  a.csv = "amr_bench.csv";
  a.grid = 48;
  a.width = a.height = 160;
  a.spp = 16;
  tessera::bench::parse_args(argc, argv, a, [&](const std::string& s, auto next) {
    if (s == "--levels") a.levels = std::atoi(next());
    else if (s == "--ratio") a.ratio = std::atoi(next());
    else if (s == "--macrocell") a.macrocell = std::atoi(next());
    else if (s == "--haze") a.haze = std::atof(next());
    else return false;
    return true;
  });
  if (a.levels < 1 || a.levels > 4 || (a.ratio != 2 && a.ratio != 4) || a.grid < 8) {
    std::fprintf(stderr, "--levels 1..4, --ratio 2 or 4, --grid >= 8\n");
    std::exit(2);
  }
  return a;
}

const Vec3 kSpot(0.62, 0.55, 0.45);
double g_haze = 0.08;

double field(const Vec3& x) {
  const Vec3 d = x - kSpot;
  const double spot = std::exp(-glm::dot(d, d) / (2.0 * 0.03 * 0.03));
  const double haze = g_haze * (1.0 + std::sin(6.0 * x.x) * std::cos(5.0 * x.y + 2.0 * x.z));
  return std::min(1.0, spot + haze);
}

/// Cells [lo, lo + n)^3 of a level with `cells` cells per axis over the unit cube, sampled at
/// their centres.
std::vector<float> sample(std::int64_t cells, const std::int64_t lo[3], const std::int64_t n[3]) {
  std::vector<float> v(static_cast<std::size_t>(n[0] * n[1] * n[2]));
  std::size_t q = 0;
  const double h = 1.0 / static_cast<double>(cells);
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i)
        v[q++] = static_cast<float>(field(Vec3((lo[0] + i + 0.5) * h, (lo[1] + j + 0.5) * h, (lo[2] + k + 0.5) * h)));
  return v;
}

tessera::SceneDesc scene(const Args& a, std::int64_t cells0, int macrocell) {
  tessera::SceneDesc s;
  s.geometry.association = tessera::Association::Cell;
  s.geometry.spacing = Vec3(1.0 / static_cast<double>(cells0));
  s.tf.density_scale = 60.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.3, 1.0}, {0.05, 0.4, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.3, 0.5, 0.9), Color(0.95, 0.6, 0.3)});
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(0.3);
  s.lights.push_back(tessera::SphereLightDesc{Vec3(1.5, 1.8, -0.5), 0.3, Color(30.0)});
  s.camera.position = Vec3(0.5, 0.6, -1.6);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 38.0;
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 4;
  s.integrator.macrocell = macrocell;
  s.image = {a.width, a.height, a.spp, 0.0};
  s.options.threads = a.threads;
  s.options.seed = 1;
  return s;
}

struct Result {
  double best = 1e300;
  tessera::RenderStats stats;
  std::vector<float> rgb;
};

void run(const tessera::PreparedScene& ps, Result& r) {
  tessera::Film film(ps.desc().image.width, ps.desc().image.height);
  tessera::RenderStats st;
  const auto t0 = Clock::now();
  tessera::render(ps, film, st);
  const double t = std::chrono::duration<double>(Clock::now() - t0).count();
  if (t < r.best) r.best = t;
  r.stats = st;
  r.rgb.clear();
  for (const tessera::PixelSums& p : film.pixels()) r.rgb.push_back(static_cast<float>(p.lum / p.n));
}

double rmse(const std::vector<float>& a, const std::vector<float>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
  return std::sqrt(s / static_cast<double>(a.size()));
}

}  // namespace

int main(int argc, char** argv) {
  const Args a = parse(argc, argv);
  g_haze = a.haze;
  const std::int64_t n0 = a.grid;
  // The hierarchy: level l over the cube of side 1 / 2^(l+1) around the spot
  std::vector<std::vector<float>> data;
  std::vector<tessera::AmrPatch> patches;
  tessera::AmrField f;
  f.dtype = tessera::DType::Float32;
  f.nlevels = a.levels;
  for (int l = 0; l + 1 < a.levels; ++l) f.ratio[l] = a.ratio;
  for (int ax = 0; ax < 3; ++ax) f.dims[ax] = n0;
  std::uint64_t samples = 0;
  for (int l = 0; l < a.levels; ++l) {
    const std::int64_t cells = n0 * f.scale(l);
    std::int64_t lo[3], n[3];
    for (int ax = 0; ax < 3; ++ax) {
      if (l == 0) {
        lo[ax] = 0;
        n[ax] = cells;
        continue;
      }
      // Aligned to the level above (multiples of the ratio), centred on the spot
      const double side = 1.0 / std::pow(2.0, l + 1);
      const std::int64_t r = a.ratio;
      std::int64_t c0 = static_cast<std::int64_t>((kSpot[ax] - 0.5 * side) * static_cast<double>(cells) / r) * r;
      std::int64_t w = static_cast<std::int64_t>(side * static_cast<double>(cells) / r) * r;
      c0 = std::clamp<std::int64_t>(c0, 0, cells - w);
      lo[ax] = c0;
      n[ax] = w;
    }
    data.push_back(sample(cells, lo, n));
    tessera::AmrPatch p;
    p.level = l;
    for (int ax = 0; ax < 3; ++ax) p.offset[ax] = lo[ax];
    samples += static_cast<std::uint64_t>(n[0] * n[1] * n[2]);
    patches.push_back(p);
    patches.back().view = tessera::FieldView::contiguous(data.back().data(), tessera::DType::Float32, n[0], n[1], n[2]);
  }
  f.patches = patches;
  // The uniform field at the finest resolution
  const std::int64_t nf = n0 * f.scale(a.levels - 1);
  const std::int64_t zero[3] = {0, 0, 0}, all[3] = {nf, nf, nf};
  const std::vector<float> fine = sample(nf, zero, all);
  const tessera::FieldView fine_view = tessera::FieldView::contiguous(fine.data(), tessera::DType::Float32, nf, nf, nf);

  const tessera::PreparedScene uniform = tessera::prepare(fine_view, scene(a, nf, a.macrocell));
  const tessera::PreparedScene amr = tessera::prepare(f, scene(a, n0, a.macrocell), nullptr);
  const int half = std::max(1, a.macrocell / 2);
  const tessera::PreparedScene amr_half = tessera::prepare(f, scene(a, n0, half), nullptr);
  // The noise floor: the uniform field with another seed
  tessera::SceneDesc other = scene(a, nf, a.macrocell);
  other.options.seed = 2;
  const tessera::PreparedScene uniform2 = tessera::prepare(fine_view, other);
  Result ru, ra, rh, r2;
  run(uniform2, r2);
  for (int r = 0; r < a.reps; ++r) {
    run(uniform, ru);
    run(amr, ra);
    run(amr_half, rh);
  }
  const double spp_total = double(a.width) * a.height * a.spp;
  std::printf(
      "amr_bench: level 0 %lld^3 cells, %d levels of ratio %d, haze %g, %.2f M samples in the hierarchy vs %.2f M in "
      "the uniform %lld^3 field; %dx%d, %d spp, %d thread(s), best of %d\n",
      static_cast<long long>(n0), a.levels, a.ratio, a.haze, samples / 1e6, double(nf) * nf * nf / 1e6,
      static_cast<long long>(nf), a.width, a.height, a.spp, a.threads, a.reps);
  std::printf("%-28s %9s %8s %14s %14s %12s\n", "variant", "time s", "x unif", "lookups/sample", "M lookups/s",
              "rmse vs unif");
  std::ofstream csv(a.csv, std::ios::app);
  const auto row = [&](const char* name, const Result& r, int edge) {
    const double lk = static_cast<double>(r.stats.density_lookups());
    std::printf("%-28s %9.3f %8.3f %14.2f %14.2f %12.5f\n", name, r.best, r.best / ru.best, lk / spp_total,
                lk / r.best / 1e6, rmse(r.rgb, ru.rgb));
    csv << name << "," << n0 << "," << a.levels << "," << a.ratio << "," << edge << "," << r.best << ","
        << r.best / ru.best << "," << lk / spp_total << "," << rmse(r.rgb, ru.rgb) << "\n";
  };
  row("uniform finest", ru, a.macrocell);
  row("uniform finest, other seed", r2, a.macrocell);
  row("hierarchy, macrocell E", ra, a.macrocell);
  row("hierarchy, macrocell E/2", rh, half);
  return 0;
}
