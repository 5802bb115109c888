// The adapter's call over an unstructured hex mesh cut into slabs over the ranks, per call, as a
// simulation with a fixed mesh sees it (mesh_insitu_bench's modes, under MPI): new values every
// step; the geometry the same (found by each rank's hash), promised the same
// (tessera_mesh_unchanged), or moved a little every step. With several ranks every rank
// receives every rank's domains; while the geometry holds only the values move. Not a test:
// rank 0 prints the slowest rank's seconds per call (median of the steps after the first), the
// bytes a rank received in the exchange, the most bytes a rank copied to its GPU (with
// --device cuda), and writes a CSV.
//
//   mpirun -n P mesh_mpi_bench [--cells N] [--steps S] [--csv PATH] [--threads T]
//                              [--only moved|same|promised] [--device auto|cpu|cuda]
//   (defaults: 48, 6, mesh_mpi_bench.csv, 1 thread per rank, every mode, auto)
#include <tessera/adapter.h>

#include "mesh_call_bench.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

struct Row {
  std::string mode;
  double call_s = 0.0, prepare_s = 0.0;
  int reused = 0, values_only = 0;
  double exchange_mb = 0.0, to_device_mb = 0.0;
};

double slowest(double t) {
  double m = 0.0;
  MPI_Allreduce(&t, &m, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  tessera::bench::MeshCallArgs args;
  args.cells = 48;
  args.csv = "mesh_mpi_bench.csv";
  args.threads = 1;
  if (const std::string bad = tessera::bench::parse_mesh_call_args(argc, argv, args); !bad.empty()) {
    if (rank == 0) std::fprintf(stderr, "mesh_mpi_bench: unknown flag %s\n", bad.c_str());
    MPI_Finalize();
    return 2;
  }
  const std::int64_t cells = args.cells;
  const int steps = args.steps;
  const std::string csv = args.csv;
  const int threads = args.threads;
  // One directory for every rank, named by rank 0
  long id = static_cast<long>(::getpid());
  MPI_Bcast(&id, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  const fs::path dir = fs::temp_directory_path() / ("mesh_mpi_bench_" + std::to_string(id));
  const fs::path config = dir / "bench.yaml";
  if (rank == 0) {
    fs::create_directories(dir);
    std::ofstream(config) << tessera::bench::mesh_call_config((dir / "out").string(), threads, args.device);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const std::int64_t n[3] = {cells + 1, cells + 1, cells + 1};
  const std::int64_t k0 = cells * rank / size, k1 = cells * (rank + 1) / size;  // this rank's slab of cells
  std::vector<Row> rows;
  int failed = 0;
  for (const std::string& mode : tessera::bench::mesh_call_modes(args)) {
    tessera_test::MeshBlock block(n, k0, std::max(k1, k0 + 1));
    std::vector<tessera_mesh_domain> domains;
    if (k1 > k0) domains.push_back(block.domain(tessera_test::MeshBlock::Form::Hexes));
    tessera::insitu::Adapter ad;
    ad.set_quiet(true);
    if (ad.open(config.string(), MPI_Comm_c2f(MPI_COMM_WORLD)) != TESSERA_OK) {
      if (rank == 0) std::fprintf(stderr, "mesh_mpi_bench: %s\n", ad.last_error().c_str());
      failed = 1;
      break;
    }
    std::vector<double> call, prepare, bytes, to_device;
    Row row{mode};
    for (int s = 1; s <= steps && !failed; ++s) {
      tessera::bench::mesh_call_step(mode, s, block, ad);
      MPI_Barrier(MPI_COMM_WORLD);
      const auto t0 = std::chrono::steady_clock::now();
      const tessera_status status = ad.execute_mesh_domains(s, 0.1 * s, domains);
      const double t = slowest(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      if (status != TESSERA_OK) {  // the same status on every rank
        if (rank == 0) std::fprintf(stderr, "mesh_mpi_bench: %s\n", ad.last_error().c_str());
        failed = 1;
        break;
      }
      if (s == 1) continue;
      const tessera::insitu::RenderResult& r = ad.last_results().at(0);
      call.push_back(t);
      prepare.push_back(slowest(r.prepare_seconds));
      bytes.push_back(static_cast<double>(r.mesh_exchange_bytes));
      to_device.push_back(slowest(static_cast<double>(r.stats.bytes_to_device)));
      row.reused += r.mesh_layout_reused ? 1 : 0;
      row.values_only += r.mesh_values_only ? 1 : 0;
    }
    if (failed) break;
    row.call_s = tessera::bench::median(call);
    row.prepare_s = tessera::bench::median(prepare);
    row.exchange_mb = tessera::bench::median(bytes) * 1e-6;
    row.to_device_mb = tessera::bench::median(to_device) * 1e-6;
    rows.push_back(row);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) {
    fs::remove_all(dir);
    if (!failed) {
      std::printf("%lld^3 hexes in %d slabs (ranks), %d thread(s) per rank, 32x32, 1 spp, steps 2..%d\n",
                  static_cast<long long>(cells), size, threads, steps);
      std::printf("%-12s %10s %12s %8s %12s %14s %14s\n", "geometry", "call_s", "prepare_s", "reused", "values_only",
                  "exchange_MB", "to_device_MB");
      std::ofstream out(csv);
      out << "geometry,cells,ranks,threads,steps,call_s,prepare_s,layout_reused_calls,values_only_calls,"
             "exchange_mb_per_rank,to_device_mb_most\n";
      for (const Row& r : rows) {
        std::printf("%-12s %10.4f %12.4f %5d/%d %9d/%d %14.3f %14.3f\n", r.mode.c_str(), r.call_s, r.prepare_s,
                    r.reused, steps - 1, r.values_only, steps - 1, r.exchange_mb, r.to_device_mb);
        out << '"' << r.mode << "\"," << cells * cells * cells << ',' << size << ',' << threads << ',' << steps << ','
            << r.call_s << ',' << r.prepare_s << ',' << r.reused << ',' << r.values_only << ',' << r.exchange_mb << ','
            << r.to_device_mb << '\n';
      }
      std::printf("wrote %s\n", csv.c_str());
    }
  }
  MPI_Finalize();
  return failed;
}
