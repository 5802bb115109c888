// Replicated against distributed mode (docs/mpi.md): per rank count, render time, bytes moved
// per render, the field memory each rank holds (replica share or cache + directory) and the
// process's peak resident memory. Run one mode per process, so that peak memory is the mode's
// own. Not a test: rank 0 prints the figures and appends one CSV row.
//
//   mpirun -n P distributed_bench --mode replicated|distributed [--csv FILE] [--grid N]
//          [--image W H] [--spp S] [--reps R] [--threads T] [--ranks-per-node K] [--multiple]
//          [--cache-fraction F] [--shift S] [--morton] [--device-slab]
//
// --device-slab (distributed mode): each rank's slab is a simulation's device array on a host
// emulation of a GPU (core/src/cuda/gpu_emulation.h) and the render runs on that "GPU", as
// the adapter runs it: the slab stays where it is (FieldBlock::on_device), the summary is
// made from it on the device and only the bricks asked for are copied to the host; the bytes
// copied ("from device") are printed beside the slab's bytes, which replicated mode or the
// earlier staging copied whole every call. Times are the emulation's, not a GPU's.
//
// Defaults: distributed_bench.csv, 96^3 float32, 128x128, 8 spp, 2 reps, 1 thread per rank,
// single scattering. The cache is sized as the adapter sizes it without a memory limit: 40% of
// the global field (field_plan.h; --cache-fraction changes it), with the adapter's brick size
// (--shift changes it), tiles in row-major order (--morton: Morton order).
// scripts/run_distributed_bench.sh and scripts/run_distributed_cache_sweep.sh run the sweeps.
#include "bench_args.h"
#include "data/field_plan.h"
#include "mpi/parallel_context_mpi.h"
#include "mpi_bench_field.h"

#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"

#include <tessera/byte_span.h>
#include <tessera/render.h>

#include <mpi.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

using tessera::Color;
using tessera::Vec3;
using tessera::insitu::MpiParallelContext;

namespace {

using Clock = std::chrono::steady_clock;

struct Args : tessera::bench::BenchArgs {
  std::string mode = "distributed";
  int ranks_per_node = 0;
  bool multiple = false, morton = false, device_slab = false;
  double cache_fraction = tessera::insitu::kCacheFieldFraction;  ///< --cache-fraction
  int shift = 0;  ///< --shift: log2 of the brick edge; 0 = as the adapter picks it
};

Args parse(int argc, char** argv) {
  Args a;
  a.csv = "distributed_bench.csv";
  a.reps = 2;
  tessera::bench::parse_args(argc, argv, a, [&](const std::string& s, auto next) {
    if (s == "--mode") a.mode = next();
    else if (s == "--ranks-per-node") a.ranks_per_node = std::atoi(next());
    else if (s == "--multiple") a.multiple = true;
    else if (s == "--morton") a.morton = true;
    else if (s == "--device-slab") a.device_slab = true;
    else if (s == "--cache-fraction") a.cache_fraction = std::atof(next());
    else if (s == "--shift") a.shift = std::atoi(next());
    else return false;
    return true;
  });
  if (a.mode != "replicated" && a.mode != "distributed") {
    std::fprintf(stderr, "--mode replicated|distributed\n");
    std::exit(2);
  }
  return a;
}

tessera::SceneDesc make_scene(const Args& a) {
  tessera::SceneDesc s = tessera::bench::heat_blobs_scene(a.grid, 8.0);
  s.tf.density_scale = 70.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.08, 0.45, 1.0}, {0.004, 0.004, 0.25, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.25, 0.45, 0.95), Color(1.0, 0.85, 0.55)});
  s.camera.position = Vec3(2.2, -1.3, 1.3);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.integrator.scattering = a.multiple ? tessera::Scattering::Multiple : tessera::Scattering::Single;
  s.image = {a.width, a.height, a.spp, 0.0};
  if (a.morton) s.options.order = tessera::TileOrder::Morton;
  s.options.threads = a.threads;
  return s;
}

double peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) * 1024.0;
}

}  // namespace

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Args a = parse(argc, argv);
  const bool distributed = a.mode == "distributed" && size > 1;
  std::optional<tessera::cuda::ScopedGpuEmulation> gpu;
  if (a.device_slab) gpu.emplace(tessera::cuda::emulated_backend());
  {
    MpiParallelContext ctx(MPI_COMM_WORLD, a.ranks_per_node);
    // This rank's slab along k, C order with one ghost layer per side (as a simulation holds it)
    const tessera::bench::KSlab slab(a.grid, rank, size);
    const tessera::FieldView& view = slab.view;
    const tessera::insitu::GlobalPlacement& where = slab.where;
    const std::int64_t n = a.grid;
    tessera::SceneDesc scene = make_scene(a);
    tessera::insitu::FieldBlock block;  // the slab as the adapter hands it on
    block.view = view;
    for (int q = 0; q < 3; ++q) block.offset[q] = where.offset[q];
    if (a.device_slab) {
      tessera::cuda::emulated_declare_device_memory(*tessera::cuda::gpu_emulation(), slab.local.data(),
                                                    slab.local.size() * sizeof(float));
      block.on_device = distributed;
      scene.options.device = tessera::Device::Cuda;
    }
    const double slab_bytes = static_cast<double>(tessera::byte_span(view).bytes());
    const double field_bytes = 4.0 * static_cast<double>(n * n * n);
    const int shift = a.shift > 0 ? a.shift : tessera::insitu::brick_shift(where.global_dims);
    const tessera::BrickGrid grid = tessera::BrickGrid::make(where.global_dims, tessera::DType::Float32, shift);
    const std::size_t capacity = std::max<std::size_t>(
        1, static_cast<std::size_t>(a.cache_fraction * field_bytes / static_cast<double>(grid.slot_bytes())));

    double best_render = 1e300, best_total = 1e300, moved = 0.0, held = 0.0;
    double fetched = 0.0, flushes = 0.0, from_device = 0.0, slabs = 0.0;
    for (int rep = 0; rep < a.reps; ++rep) {
      MPI_Barrier(MPI_COMM_WORLD);
      const auto t0 = Clock::now();
      tessera::PreparedScene prepared;
      double mine_held = 0.0;
      if (distributed) {
        const tessera::PagedField paged =
            ctx.distribute_blocks({&block, 1}, where.global_dims, tessera::DType::Float32, shift, capacity);
        tessera::FieldView dims_only;
        for (int q = 0; q < 3; ++q) dims_only.dims[q] = n;
        const auto summary = ctx.summarize_blocks({&block, 1}, where.global_dims, tessera::DType::Float32,
                                                  tessera::majorant_edge(dims_only, scene.integrator));
        ctx.serve_while([&] { prepared = tessera::prepare(paged, scene, summary); });
        mine_held = static_cast<double>(ctx.report().cache_bytes);
      } else {
        prepared = tessera::prepare(ctx.assemble(view, where), scene);
        mine_held = static_cast<double>(ctx.replica_bytes()) / ctx.node_size();
      }
      tessera::Film film(a.width, a.height);
      tessera::RenderStats stats;
      const auto t1 = Clock::now();
      ctx.render(prepared, film, stats);
      const auto t2 = Clock::now();
      const auto& r = ctx.report();
      if (a.device_slab && rep == 0 && rank == 0)
        std::printf("distributed_bench: rendered on the emulated GPU: %.2f MB to the device, %.2f MB to the host\n",
                    static_cast<double>(stats.bytes_to_device) / 1e6, static_cast<double>(stats.bytes_to_host) / 1e6);
      const double copies[2] = {static_cast<double>(ctx.paged_bytes_from_device()), slab_bytes};
      MPI_Reduce(copies, &from_device, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
      MPI_Reduce(copies + 1, &slabs, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
      const double mine[6] = {std::chrono::duration<double>(t2 - t1).count(),
                              std::chrono::duration<double>(t2 - t0).count(),
                              static_cast<double>(r.assemble_bytes + r.render_bytes + r.bricks.bytes_received +
                                                  16 * r.bricks.requests_sent),
                              static_cast<double>(r.cache.fetched),
                              static_cast<double>(r.cache.flushes),
                              mine_held};
      double mx[6], sum[6];
      MPI_Reduce(mine, mx, 6, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
      MPI_Reduce(mine, sum, 6, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
      best_render = std::min(best_render, mx[0]);
      best_total = std::min(best_total, mx[1]);
      moved = sum[2];
      fetched = sum[3];
      flushes = sum[4];
      held = mx[5];
    }
    double rss = peak_rss_bytes(), rss_max = 0.0;
    MPI_Reduce(&rss, &rss_max, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    if (rank == 0) {
      std::printf("distributed_bench: %s, %d rank(s), %d node(s), grid %d^3 (%.1f MB), %dx%d %d spp, %s scattering: "
                  "render %.3f s (prepare+render %.3f s), moved %.2f MB/render, field memory/rank %.2f MB "
                  "(%.0f%% of the field), peak RSS/rank %.1f MB, bricks fetched %.0f, flushes %.0f\n",
                  a.mode.c_str(), size, ctx.node_count(), a.grid, field_bytes / 1e6, a.width, a.height, a.spp,
                  a.multiple ? "multiple" : "single", best_render, best_total, moved / 1e6, held / 1e6,
                  100.0 * held / field_bytes, rss_max / 1e6, fetched, flushes);
      if (a.device_slab)
        std::printf("distributed_bench: device slabs (emulated GPU): %.2f MB copied from device memory per render "
                    "(all ranks), the slabs hold %.2f MB (%.0f%%)\n",
                    from_device / 1e6, slabs / 1e6, 100.0 * from_device / slabs);
      const bool fresh = !std::filesystem::exists(a.csv);
      std::ofstream out(a.csv, std::ios::app);
      if (fresh)
        out << "mode,ranks,nodes,grid,field_bytes,image,spp,scattering,threads,render_s,prepare_render_s,bytes_moved,"
               "field_bytes_per_rank,peak_rss_per_rank,bricks_fetched,flushes,device_slab,bytes_from_device\n";
      out << a.mode << "," << size << "," << ctx.node_count() << "," << a.grid << "," << field_bytes << "," << a.width
          << "x" << a.height << "," << a.spp << "," << (a.multiple ? "multiple" : "single") << "," << a.threads << ","
          << best_render << "," << best_total << "," << moved << "," << held << "," << rss_max << "," << fetched << ","
          << flushes << "," << (a.device_slab ? 1 : 0) << "," << from_device << "\n";
    }
  }
  MPI_Finalize();
  return 0;
}
