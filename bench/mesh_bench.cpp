// Curvilinear and unstructured meshes (mesh.h), core only: the time to check a mesh (in full,
// and its indices alone as for a mesh promised unchanged) and build its tables (per million
// elements), and the render time of the hex mesh built from a uniform
// grid's cells (and of those cells cut into 6 tets each) against that grid, same field, same
// scene, equal spp. Not a test: prints the figures and writes CSV rows.
//
//   mesh_bench [--csv FILE] [--grid N] [--image W H] [--spp S] [--reps R] [--threads T]
//              [--device cpu|cuda]
//
// --device cuda renders every variant on the GPU (a build with CUDA; the three variants' host
// arrays copied to the device with the scene, prepare stays on the host).
//
// The scene: N^3 cells over the unit cube, a smooth blobby field, multiple scattering lit by
// a sphere light and a constant background. Each variant renders `reps` times; the fastest is
// kept. --threads T: the threads of prepare, the checks and the render alike (0 = all).
// Defaults: mesh_bench.csv, N = 48, 160x160, 16 spp, 3 reps, 1 thread.
#include <tessera/mesh.h>
#include <tessera/render.h>

#include "bench_args.h"
#include "test_mesh_support.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

using tessera::Color;
using tessera::Vec3;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double blobby(const Vec3& p) {
  const Vec3 d = p - Vec3(0.55, 0.45, 0.5);
  return std::exp(-8.0 * glm::dot(d, d)) + 0.3 * std::sin(6.0 * p.x) * std::cos(5.0 * p.z);
}

tessera::SceneDesc make_scene(const tessera::bench::BenchArgs& a, tessera::Device device) {
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / a.grid);
  s.tf.lo = -0.3;
  s.tf.hi = 1.2;
  s.tf.density_scale = 6.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.05, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.6, 0.5, 0.4));
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(0.5);
  s.lights.push_back(tessera::SphereLightDesc{Vec3(1.6, 1.8, -0.6), 0.3, Color(25.0)});
  s.camera.position = Vec3(1.1, 1.4, -2.1);
  s.camera.look_at = Vec3(0.5);
  s.camera.fov_deg = 32.0;
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 6;
  s.image = {a.width, a.height, a.spp, 0.0};
  s.options.threads = a.threads;
  s.options.device = device;
  return s;
}

struct Row {
  std::string variant;
  std::size_t elements = 0;
  double prepare_s = 0.0, render_s = 0.0, mean = 0.0;
};

/// The fastest of `reps` prepares and renders of `field` (a FieldView or a Mesh).
template <class F>
Row run(const std::string& name, const F& field, std::size_t elements, const tessera::SceneDesc& s, int reps) {
  Row r{name, elements, 1e300, 1e300, 0.0};
  for (int i = 0; i < reps; ++i) {
    auto t0 = Clock::now();
    const tessera::PreparedScene ps = tessera::prepare(field, s);
    r.prepare_s = std::min(r.prepare_s, seconds_since(t0));
    tessera::Film film(s.image.width, s.image.height);
    tessera::RenderStats st;
    t0 = Clock::now();
    tessera::render(ps, film, st);
    r.render_s = std::min(r.render_s, seconds_since(t0));
    double sum = 0.0;
    for (const tessera::PixelSums& p : film.pixels()) sum += p.lum / static_cast<double>(p.n);
    r.mean = sum / static_cast<double>(film.pixels().size());
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  tessera::bench::BenchArgs a;
  a.csv = "mesh_bench.csv";
  a.grid = 48;
  a.width = a.height = 160;
  a.spp = 16;
  tessera::Device device = tessera::Device::Cpu;
  tessera::bench::parse_args(argc, argv, a, [&](const std::string& flag, auto next) {
    if (flag != "--device") return false;
    const std::string d = next();
    if (d != "cpu" && d != "cuda") {
      std::fprintf(stderr, "--device: cpu or cuda, not %s\n", d.c_str());
      std::exit(2);
    }
    device = d == "cuda" ? tessera::Device::Cuda : tessera::Device::Cpu;
    return true;
  });
  const int n = a.grid;
  const tessera::SceneDesc s = make_scene(a, device);
  const tessera_mesh_test::ElementList hexes = tessera_mesh_test::grid_hexes(n, n, n, Vec3(0.0), Vec3(1.0 / n), blobby);
  const tessera_mesh_test::ElementList tets = tessera_mesh_test::hexes_to_tets(hexes);
  const tessera::FieldView grid =
      tessera::FieldView::contiguous(hexes.value.data(), tessera::DType::Float64, n + 1, n + 1, n + 1);
  const tessera_mesh_test::OwnedMesh hex_mesh = tessera_mesh_test::one_domain(hexes);
  const tessera_mesh_test::OwnedMesh tet_mesh = tessera_mesh_test::one_domain(tets);
  std::vector<Row> rows;
  try {
    rows.push_back(run("grid", grid, hexes.element.size(), s, a.reps));
    rows.push_back(run("hex_mesh", hex_mesh.mesh, hexes.element.size(), s, a.reps));
    rows.push_back(run("tet_mesh", tet_mesh.mesh, tets.element.size(), s, a.reps));
  } catch (const std::exception& e) {  // e.g. --device cuda without a GPU
    std::fprintf(stderr, "mesh_bench: %s\n", e.what());
    return 1;
  }
  // check_mesh alone, per million elements, on as many threads as prepare (--threads; 0 = all)
  double check_hex = 0.0, check_tet = 0.0, indices_hex = 0.0, indices_tet = 0.0, receipt_hex = 1e300;
  tbb::task_arena arena(a.threads > 0 ? a.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    auto t0 = Clock::now();
    const tessera::MeshChecked hex_receipt = tessera::check_mesh(hex_mesh.mesh);
    check_hex = seconds_since(t0);
    // prepare given that check's receipt (as the adapter's pass does on one rank): no second check
    for (int i = 0; i < a.reps; ++i) {
      t0 = Clock::now();
      const tessera::PreparedScene ps = tessera::prepare(hex_mesh.mesh, s, nullptr, hex_receipt);
      receipt_hex = std::min(receipt_hex, seconds_since(t0));
    }
    t0 = Clock::now();
    tessera::check_mesh(tet_mesh.mesh);
    check_tet = seconds_since(t0);
    // check_mesh_indices (what a promised-unchanged mesh is checked with: no shapes)
    t0 = Clock::now();
    tessera::check_mesh_indices(hex_mesh.mesh);
    indices_hex = seconds_since(t0);
    t0 = Clock::now();
    tessera::check_mesh_indices(tet_mesh.mesh);
    indices_tet = seconds_since(t0);
  });
  std::printf("%dx%dx%d cells, %dx%d, %d spp, %d thread(s), on the %s\n", n, n, n, a.width, a.height, a.spp, a.threads,
              device == tessera::Device::Cuda ? "GPU" : "CPU");
  std::printf("%-9s %10s %12s %14s %10s %12s %10s\n", "variant", "elements", "prepare_s", "prepare_s/Mel", "render_s",
              "render/grid", "mean");
  std::ofstream csv(a.csv);
  csv << "variant,device,elements,grid,width,height,spp,threads,prepare_s,prepare_s_per_million,"
         "check_s_per_million,render_s,render_over_grid,mean_luminance\n";
  for (const Row& r : rows) {
    const double mel = static_cast<double>(r.elements) * 1e-6;
    const double check = r.variant == "hex_mesh" ? check_hex : r.variant == "tet_mesh" ? check_tet : 0.0;
    std::printf("%-9s %10zu %12.4f %14.4f %10.3f %12.2f %10.5f\n", r.variant.c_str(), r.elements, r.prepare_s,
                r.prepare_s / mel, r.render_s, r.render_s / rows[0].render_s, r.mean);
    csv << r.variant << ',' << (device == tessera::Device::Cuda ? "cuda" : "cpu") << ',' << r.elements << ',' << n
        << ',' << a.width << ',' << a.height << ',' << a.spp << ',' << a.threads << ',' << r.prepare_s << ','
        << r.prepare_s / mel << ',' << check / mel << ',' << r.render_s << ',' << r.render_s / rows[0].render_s << ','
        << r.mean << '\n';
  }
  std::printf("check_mesh: hex %.4f s/Mel, tet %.4f s/Mel\n", check_hex / (hexes.element.size() * 1e-6),
              check_tet / (tets.element.size() * 1e-6));
  std::printf("check_mesh_indices: hex %.4f s/Mel, tet %.4f s/Mel\n", indices_hex / (hexes.element.size() * 1e-6),
              indices_tet / (tets.element.size() * 1e-6));
  std::printf("prepare given check_mesh's receipt: hex %.4f s/Mel (without: %.4f)\n",
              receipt_hex / (hexes.element.size() * 1e-6), rows[1].prepare_s / (hexes.element.size() * 1e-6));
  std::printf("wrote %s\n", a.csv.c_str());
  return 0;
}
