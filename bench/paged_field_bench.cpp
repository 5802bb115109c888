// Demand-paged field (brick_cache.h), core side: render time of the blobs scene read in place
// (plain FieldView) vs through a PagedFieldView (own block in place, every vertex in place,
// or every vertex through the cache with all bricks resident, or with a cache of 1/8 of the
// bricks), served by an in-process thread (tests/core/fake_brick_service.h) instead of MPI.
// Not a test: prints the figures and writes CSV rows.
//
//   paged_field_bench [--csv FILE] [--grid N] [--image W H] [--spp S] [--reps R] [--threads T]
//                     [--shift S] [--no-small-cache] [--device cpu|cuda]
//
// --device cuda renders every mode on the GPU (a build with CUDA): the paged modes through the
// device's pool of bricks, launches replayed as they miss (docs/gpu.md, "Distributed fields on
// the GPU"); the small cache's reps each start from a fresh prepared scene (an empty pool).
//
// Defaults: paged_field_bench.csv, 96^3 float32, 192x192, 8 spp, 3 reps (the best is kept),
// 1 thread, bricks of 2^5 = 32 vertices.
#include <tessera/brick_cache.h>
#include <tessera/render.h>

#include "bench_args.h"
#include "fake_brick_service.h"
#include "test_support.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

using tessera::Color;
using tessera::Vec3;

namespace {

using Clock = std::chrono::steady_clock;

struct Args : tessera::bench::BenchArgs {
  int shift = 5;
  bool small_cache = true;  ///< --no-small-cache skips the (slow) 1/8 cache
  tessera::Device device = tessera::Device::Cpu;
};

Args parse(int argc, char** argv) {
  Args a;
  a.csv = "paged_field_bench.csv";
  a.width = a.height = 192;
  tessera::bench::parse_args(argc, argv, a, [&](const std::string& s, auto next) {
    if (s == "--shift") a.shift = std::atoi(next());
    else if (s == "--no-small-cache") a.small_cache = false;
    else if (s == "--device") {
      const std::string d = next();
      if (d != "cpu" && d != "cuda") {
        std::fprintf(stderr, "--device: cpu or cuda, not %s\n", d.c_str());
        std::exit(2);
      }
      a.device = d == "cuda" ? tessera::Device::Cuda : tessera::Device::Cpu;
    } else return false;
    return true;
  });
  return a;
}

tessera::SceneDesc blobs_scene(const Args& a) {
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (a.grid - 1));
  s.tf.density_scale = 40.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.2, 1.0}, {0.0, 0.5, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.9, 0.6, 0.3), Color(0.3, 0.7, 0.95)});
  s.camera.position = Vec3(0.5, 0.6, -1.6);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 40.0;
  s.lights.push_back(tessera::SphereLightDesc{Vec3(1.5, 1.5, -0.5), 0.3, Color(8.0)});
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(0.1);
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 8;
  s.integrator.macrocell = 8;
  s.image = {a.width, a.height, a.spp, 0.0};
  s.options.threads = a.threads;
  s.options.seed = 5;
  s.options.device = a.device;
  return s;
}

struct Row {
  std::string mode;
  std::size_t capacity = 0;
  double seconds = 0.0;
  tessera::BrickCacheStats cache;
  std::uint64_t to_device = 0;  ///< bytes copied to the GPU in the best rep (--device cuda)
  bool same = true;
  std::string refused;  ///< the render's error, when it refused the mode (e.g. a pool too small)
};

}  // namespace

int run(const Args& a);

int main(int argc, char** argv) {
  const Args a = parse(argc, argv);
  try {
    return run(a);
  } catch (const std::exception& e) {  // e.g. --device cuda without a GPU
    std::fprintf(stderr, "paged_field_bench: %s\n", e.what());
    return 1;
  }
}

int run(const Args& a) {
  const std::vector<float> data = tessera_test::blobby_field(a.grid, a.grid, a.grid);
  const tessera::FieldView whole =
      tessera::FieldView::contiguous(data.data(), tessera::DType::Float32, a.grid, a.grid, a.grid);
  const tessera::SceneDesc scene = blobs_scene(a);
  const int edge = tessera::majorant_edge(whole, scene.integrator);
  const auto summary = tessera::FieldSummary::build(whole, edge);

  // Plain
  std::vector<Row> rows;
  std::vector<tessera::PixelSums> reference;
  {
    const tessera::PreparedScene ps = tessera::prepare(whole, scene, summary);
    Row r;
    r.mode = "plain";
    r.seconds = 1e300;
    for (int rep = 0; rep < a.reps; ++rep) {
      tessera::RenderStats st;
      const auto t0 = Clock::now();
      const tessera::Film film = tessera_test::render_film(ps, &st);
      const double t = std::chrono::duration<double>(Clock::now() - t0).count();
      if (t < r.seconds) r.to_device = st.bytes_to_device;
      r.seconds = std::min(r.seconds, t);
      reference = film.pixels();
    }
    rows.push_back(r);
  }

  // Paged: (own block = whole field | no own block) x cache size; `warm`: bricks stay from the
  // previous rep (all resident after the first), else the cache is emptied before each rep
  const std::int64_t dims[3] = {a.grid, a.grid, a.grid};
  const tessera::BrickGrid grid = tessera::BrickGrid::make(dims, tessera::DType::Float32, a.shift);
  const auto all = static_cast<std::size_t>(grid.brick_count());
  struct Mode {
    const char* name;
    bool own_all;
    std::size_t capacity;
    bool warm;
  };
  const Mode modes[] = {{"paged, own block = whole field", true, 1, true},
                        {"paged, all bricks resident", false, all, true},
                        {"paged, cache of 1/8 of the bricks", false, std::max<std::size_t>(1, all / 8), false}};
  for (const Mode& m : modes) {
    if (!m.warm && !a.small_cache) continue;
    tessera::BrickCache cache(grid, m.capacity);
    tessera::PagedField f;
    f.dtype = tessera::DType::Float32;
    for (int i = 0; i < 3; ++i) f.dims[i] = dims[i];
    if (m.own_all) f.local = whole;
    f.cache = &cache;
    Row r;
    r.mode = m.name;
    r.capacity = m.capacity;
    r.seconds = 1e300;
    tessera_test::FakeBrickService service(cache, whole);
    try {
      auto ps = std::make_unique<tessera::PreparedScene>(tessera::prepare(f, scene, summary));
      if (m.warm) tessera_test::render_film(*ps);  // first touch of every brick, not timed
      for (int rep = 0; rep < a.reps; ++rep) {
        if (!m.warm) {
          cache.reset();
          // On the GPU the pool lives with the prepared scene: a fresh one starts it empty
          if (a.device == tessera::Device::Cuda && rep > 0)
            ps = std::make_unique<tessera::PreparedScene>(tessera::prepare(f, scene, summary));
        }
        tessera::RenderStats st;
        const auto t0 = Clock::now();
        const tessera::Film film = tessera_test::render_film(*ps, &st);
        const double t = std::chrono::duration<double>(Clock::now() - t0).count();
        if (t < r.seconds) r.to_device = st.bytes_to_device;
        r.seconds = std::min(r.seconds, t);
        r.same = r.same && film.pixels().size() == reference.size() &&
                 std::memcmp(film.pixels().data(), reference.data(), reference.size() * sizeof(reference[0])) == 0;
        if (!m.warm) r.cache = cache.stats();
      }
      if (m.warm) r.cache = cache.stats();
    } catch (const std::exception& e) {  // this mode refused (e.g. a path needs more bricks than the pool holds)
      r.refused = e.what();
    }
    rows.push_back(r);
  }

  const bool gpu = a.device == tessera::Device::Cuda;
  std::printf("%d^3 float32, %dx%d, %d spp, %s, bricks of %lld^3 (%zu), best of %d\n", a.grid, a.width, a.height, a.spp,
              gpu ? "GPU" : (std::to_string(a.threads) + " thread(s)").c_str(), static_cast<long long>(grid.edge()),
              all, a.reps);
  std::ofstream csv(a.csv);
  csv << "mode,device,grid,width,height,spp,threads,brick_edge,bricks,capacity,seconds,ratio_to_plain,misses,flushes,"
         "fetched,bytes_to_device,identical\n";
  for (const Row& r : rows) {
    if (!r.refused.empty()) {
      std::printf("  %-36s refused: %s\n", r.mode.c_str(), r.refused.c_str());
      csv << '"' << r.mode << "\"," << (gpu ? "cuda" : "cpu") << ',' << a.grid << ',' << a.width << ',' << a.height
          << ',' << a.spp << ',' << a.threads << ',' << grid.edge() << ',' << all << ',' << r.capacity << ",,,,,,,\n";
      continue;
    }
    std::printf("  %-36s %8.3f s  x%.3f  misses %llu  flushes %llu  fetched %llu  to device %llu  %s\n", r.mode.c_str(),
                r.seconds, r.seconds / rows[0].seconds, static_cast<unsigned long long>(r.cache.misses),
                static_cast<unsigned long long>(r.cache.flushes), static_cast<unsigned long long>(r.cache.fetched),
                static_cast<unsigned long long>(r.to_device), r.same ? "identical" : "DIFFERENT");
    csv << '"' << r.mode << "\"," << (gpu ? "cuda" : "cpu") << ',' << a.grid << ',' << a.width << ',' << a.height << ','
        << a.spp << ',' << a.threads << ',' << grid.edge() << ',' << all << ',' << r.capacity << ',' << r.seconds << ','
        << r.seconds / rows[0].seconds << ',' << r.cache.misses << ',' << r.cache.flushes << ',' << r.cache.fetched
        << ',' << r.to_device << ',' << (r.same ? 1 : 0) << '\n';
  }
  return 0;
}
