// MPI tile rendering: per-rank render time, load imbalance (max / mean), bytes moved per
// render and replica memory per node, for the dynamic tile distribution of
// MpiParallelContext and, for comparison, a static split of the tile list into contiguous
// blocks. Not a test: rank 0 prints the figures and appends CSV rows.
//
// Render time per rank is measured twice: wall time, and process CPU time (all the rank's
// threads). On a machine with fewer free cores than ranks the wall times even out (ranks that
// finish early hand their core to the others); CPU time still shows how the work was split.
//
//   mpirun -n P mpi_render_bench [--csv FILE] [--grid N] [--image W H] [--spp S] [--reps R]
//                                [--threads T] [--ranks-per-node K]
//
// Defaults: mpi_render_bench.csv, 96^3 float32, 256x256, 16 spp, 3 reps, 1 thread per rank,
// real nodes. The volume fills about half of the image, so a static split is unbalanced.
// Per-rank rows go to FILE, one summary row per mode to FILE with _summary before .csv.
// scripts/run_mpi_bench.sh runs it for 1, 2 and 4 ranks.
#include "bench_args.h"
#include "mpi/parallel_context_mpi.h"
#include "mpi_bench_field.h"

#include <tessera/render.h>

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

using tessera::Color;
using tessera::Vec3;
using tessera::insitu::MpiParallelContext;

namespace {

using Clock = std::chrono::steady_clock;

struct Args : tessera::bench::BenchArgs {
  int ranks_per_node = 0;
};

Args parse(int argc, char** argv) {
  Args a;
  a.csv = "mpi_render_bench.csv";
  a.width = a.height = 256;
  a.spp = 16;
  tessera::bench::parse_args(argc, argv, a, [&](const std::string& s, auto next) {
    if (s != "--ranks-per-node") return false;
    a.ranks_per_node = std::atoi(next());
    return true;
  });
  return a;
}

tessera::SceneDesc make_scene(const Args& a) {
  tessera::SceneDesc s = tessera::bench::heat_blobs_scene(a.grid, 6.0);
  s.tf.density_scale = 40.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.06, 0.3, 1.0}, {0.0, 0.0, 0.25, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.9, 0.5, 0.2), Color(1.0, 0.9, 0.6)});
  // Camera aimed to the right of the volume: it fills about the left half of the image.
  s.camera.position = Vec3(2.6, -1.4, 1.3);
  s.camera.look_at = Vec3(0.9, 0.9, 0.5);
  s.integrator.scattering = tessera::Scattering::Single;
  s.image = {a.width, a.height, a.spp, 0.0};
  s.options.threads = a.threads;
  return s;
}

/// Per-rank figures of one render, gathered to rank 0.
struct Sample {
  double render_s, render_cpu_s, assemble_s, tiles, grabs, assemble_bytes, render_bytes, replica_bytes, is_leader;
};

std::vector<Sample> gather(const Sample& mine, int size) {
  std::vector<Sample> all(static_cast<std::size_t>(size));
  constexpr int kN = sizeof(Sample) / sizeof(double);
  MPI_Gather(&mine, kN, MPI_DOUBLE, all.data(), kN, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  return all;
}

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::string summary_path(const std::string& csv) {
  const std::filesystem::path p(csv);
  return (p.parent_path() / (p.stem().string() + "_summary" + p.extension().string())).string();
}

std::ofstream open_csv(const std::string& path, const char* header) {
  const bool fresh = !std::filesystem::exists(path);
  std::ofstream out(path, std::ios::app);
  if (fresh) out << header << "\n";
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Args a = parse(argc, argv);
  {
    MpiParallelContext ctx(MPI_COMM_WORLD, a.ranks_per_node);

    // This rank's slab along k, C order with one ghost layer per side (as a simulation holds it)
    const tessera::bench::KSlab slab(a.grid, rank, size);
    const tessera::FieldView& view = slab.view;
    const tessera::insitu::GlobalPlacement& where = slab.where;
    const tessera::SceneDesc scene = make_scene(a);

    std::ofstream csv, summary;
    if (rank == 0) {
      csv = open_csv(a.csv, "ranks,nodes,mode,rep,rank,render_s,render_cpu_s,tiles,grabs,assemble_s,assemble_bytes,"
                            "render_bytes,replica_bytes_node");
      summary = open_csv(
          summary_path(a.csv),
          "ranks,nodes,mode,threads_per_rank,image,spp,grid,reps,render_wall_s,render_mean_s,imbalance_max_over_mean,"
          "render_cpu_max_s,render_cpu_mean_s,imbalance_cpu,"
          "bytes_moved_per_render,replica_bytes_per_node,replica_bytes_total");
      std::printf("mpi_render_bench: %d rank(s), %d node(s), %d thread(s)/rank, %dx%d %d spp, grid %d^3, %d reps\n",
                  size, ctx.node_count(), a.threads, a.width, a.height, a.spp, a.grid, a.reps);
    }

    for (const char* mode : {"dynamic", "static"}) {
      double sum_wall = 0.0, sum_mean = 0.0, sum_imb = 0.0, sum_bytes = 0.0, replica_node = 0.0, replica_total = 0.0;
      double sum_cpu_max = 0.0, sum_cpu_mean = 0.0, sum_cpu_imb = 0.0;
      std::vector<double> per_rank(static_cast<std::size_t>(size), 0.0), per_rank_cpu(per_rank),
          per_rank_tiles(per_rank);
      for (int rep = -1; rep < a.reps; ++rep) {  // rep -1: warm-up, not recorded
        Sample s{};
        MPI_Barrier(MPI_COMM_WORLD);
        auto t0 = Clock::now();
        const tessera::FieldView replica = ctx.assemble(view, where);
        s.assemble_s = std::chrono::duration<double>(Clock::now() - t0).count();
        const tessera::PreparedScene prepared = tessera::prepare(replica, scene);
        tessera::Film film(a.width, a.height);
        tessera::RenderStats stats;
        MPI_Barrier(MPI_COMM_WORLD);
        if (std::string(mode) == "dynamic") {
          ctx.render(prepared, film, stats);
          s.render_s = ctx.report().render_seconds;
          s.render_cpu_s = ctx.report().render_cpu_seconds;
          s.tiles = ctx.report().tiles;
          s.grabs = ctx.report().grabs;
          s.render_bytes = static_cast<double>(ctx.report().render_bytes);
        } else {  // contiguous blocks of the tile list, no pixel gather: the imbalance alone
          const int T = static_cast<int>(prepared.tiles().size());
          std::vector<int> mine;
          for (int t = T * rank / size; t < T * (rank + 1) / size; ++t) mine.push_back(t);
          t0 = Clock::now();
          const double cpu0 = process_cpu_seconds();
          tessera::render_tiles(prepared, mine, film, stats);
          s.render_cpu_s = process_cpu_seconds() - cpu0;
          s.render_s = std::chrono::duration<double>(Clock::now() - t0).count();
          s.tiles = static_cast<double>(mine.size());
          s.grabs = 1;
        }
        s.assemble_bytes = static_cast<double>(ctx.report().assemble_bytes);
        s.replica_bytes = static_cast<double>(size > 1 ? ctx.replica_bytes() : 0);
        s.is_leader = ctx.node_rank() == 0 ? 1.0 : 0.0;
        const std::vector<Sample> all = gather(s, size);
        if (rank != 0 || rep < 0) continue;
        double max = 0.0, mean = 0.0, bytes = 0.0, cpu_max = 0.0, cpu_mean = 0.0;
        replica_node = replica_total = 0.0;
        for (int r = 0; r < size; ++r) {
          const Sample& x = all[static_cast<std::size_t>(r)];
          max = std::max(max, x.render_s);
          cpu_max = std::max(cpu_max, x.render_cpu_s);
          cpu_mean += x.render_cpu_s / size;
          per_rank[static_cast<std::size_t>(r)] += x.render_s / a.reps;
          per_rank_cpu[static_cast<std::size_t>(r)] += x.render_cpu_s / a.reps;
          per_rank_tiles[static_cast<std::size_t>(r)] += x.tiles / a.reps;
          mean += x.render_s / size;
          bytes += x.assemble_bytes + x.render_bytes;
          if (x.is_leader > 0.0) {
            replica_node = std::max(replica_node, x.replica_bytes);
            replica_total += x.replica_bytes;
          }
          csv << size << "," << ctx.node_count() << "," << mode << "," << rep << "," << r << "," << x.render_s << ","
              << x.render_cpu_s << "," << x.tiles << "," << x.grabs << "," << x.assemble_s << "," << x.assemble_bytes
              << "," << x.render_bytes << "," << x.replica_bytes << "\n";
        }
        sum_wall += max;
        sum_mean += mean;
        sum_imb += mean > 0.0 ? max / mean : 1.0;
        sum_bytes += bytes;
        sum_cpu_max += cpu_max;
        sum_cpu_mean += cpu_mean;
        sum_cpu_imb += cpu_mean > 0.0 ? cpu_max / cpu_mean : 1.0;
      }
      if (rank == 0) {
        const double r = a.reps;
        std::printf("  %-8s render wall %.3f s (slowest rank), mean %.3f s, imbalance max/mean %.3f; "
                    "CPU max %.3f s, mean %.3f s, imbalance %.3f; moved %.2f MB/render, replica %.2f MB/node\n",
                    mode, sum_wall / r, sum_mean / r, sum_imb / r, sum_cpu_max / r, sum_cpu_mean / r, sum_cpu_imb / r,
                    sum_bytes / r / 1e6, replica_node / 1e6);
        std::printf("           per rank (wall / CPU s, tiles):");
        for (int q = 0; q < size; ++q) {
          const std::size_t u = static_cast<std::size_t>(q);
          std::printf(" %.3f/%.3f (%.0f)", per_rank[u], per_rank_cpu[u], per_rank_tiles[u]);
        }
        std::printf("\n");
        summary << size << "," << ctx.node_count() << "," << mode << "," << a.threads << "," << a.width << "x"
                << a.height << "," << a.spp << "," << a.grid << "," << a.reps << "," << sum_wall / r << ","
                << sum_mean / r << "," << sum_imb / r << "," << sum_cpu_max / r << "," << sum_cpu_mean / r << ","
                << sum_cpu_imb / r << "," << sum_bytes / r << "," << replica_node << "," << replica_total << "\n";
      }
    }
  }
  MPI_Finalize();
  return 0;
}
