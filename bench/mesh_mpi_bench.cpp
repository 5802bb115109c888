// The adapter's call over an unstructured hex mesh cut into slabs over the ranks, per call, as a
// simulation with a fixed mesh sees it (mesh_insitu_bench's modes, under MPI): new values every
// step; the geometry the same (found by each rank's hash), promised the same
// (tessera_mesh_unchanged), or moved a little every step. With several ranks every rank
// receives every rank's domains; while the geometry holds only the values move. Not a test:
// rank 0 prints the slowest rank's seconds per call (median of the steps after the first), the
// bytes a rank received in the exchange, and writes a CSV.
//
//   mpirun -n P mesh_mpi_bench [--cells N] [--steps S] [--csv PATH] [--threads T]
//                              [--only moved|same|promised]
//   (defaults: 48, 6, mesh_mpi_bench.csv, 1 thread per rank, every mode)
#include <tessera/adapter.h>

#include "mesh_blocks.h"

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
  double exchange_mb = 0.0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

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
  std::int64_t cells = 48;
  int steps = 6;
  std::string csv = "mesh_mpi_bench.csv";
  int threads = 1;
  std::string only;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--cells") cells = std::clamp<std::int64_t>(std::atoll(argv[i + 1]), 2, 1024);
    else if (flag == "--steps") steps = std::clamp(std::atoi(argv[i + 1]), 2, 1000);
    else if (flag == "--csv") csv = argv[i + 1];
    else if (flag == "--threads") threads = std::max(0, std::atoi(argv[i + 1]));
    else if (flag == "--only") only = argv[i + 1];
    else {
      if (rank == 0) std::fprintf(stderr, "mesh_mpi_bench: unknown flag %s\n", flag.c_str());
      MPI_Finalize();
      return 2;
    }
  }
  // One directory for every rank, named by rank 0
  long id = static_cast<long>(::getpid());
  MPI_Bcast(&id, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  const fs::path dir = fs::temp_directory_path() / ("mesh_mpi_bench_" + std::to_string(id));
  const fs::path config = dir / "bench.yaml";
  if (rank == 0) {
    fs::create_directories(dir);
    std::ofstream(config) << "tessera:\n  output_dir: " << (dir / "out").string() << "\n  threads: " << threads
                          << "\nrenders:\n  - name: view\n    field: f\n"
                             "    image: {width: 32, height: 32, spp: 1}\n"
                             "    camera: {position: {orbit: {azimuth: 30, elevation: 25, distance: 3}}, look_at: "
                             "center, up: [0, 0, 1], fov: 40}\n"
                             "    transfer_function: {range: auto, density_scale: 40, opacity: [[0, 0], [1, 1]]}\n";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const std::int64_t n[3] = {cells + 1, cells + 1, cells + 1};
  const std::int64_t k0 = cells * rank / size, k1 = cells * (rank + 1) / size;  // this rank's slab of cells
  std::vector<Row> rows;
  int failed = 0;
  for (const std::string mode : {"moved", "same (hash)", "promised"}) {
    if (!only.empty() && mode.rfind(only, 0) != 0) continue;
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
    std::vector<double> call, prepare, bytes;
    Row row{mode};
    for (int s = 1; s <= steps && !failed; ++s) {
      for (double& v : block.vertex_values) v = 0.98 * v + 0.01;  // new values every step
      if (mode == "moved")
        for (double& x : block.x) x += 1e-7;
      if (mode == "promised" && s > 1) ad.mesh_unchanged();
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
      row.reused += r.mesh_layout_reused ? 1 : 0;
      row.values_only += r.mesh_values_only ? 1 : 0;
    }
    if (failed) break;
    row.call_s = median(call);
    row.prepare_s = median(prepare);
    row.exchange_mb = median(bytes) * 1e-6;
    rows.push_back(row);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) {
    fs::remove_all(dir);
    if (!failed) {
      std::printf("%lld^3 hexes in %d slabs (ranks), %d thread(s) per rank, 32x32, 1 spp, steps 2..%d\n",
                  static_cast<long long>(cells), size, threads, steps);
      std::printf("%-12s %10s %12s %8s %12s %14s\n", "geometry", "call_s", "prepare_s", "reused", "values_only",
                  "exchange_MB");
      std::ofstream out(csv);
      out << "geometry,cells,ranks,threads,steps,call_s,prepare_s,layout_reused_calls,values_only_calls,"
             "exchange_mb_per_rank\n";
      for (const Row& r : rows) {
        std::printf("%-12s %10.4f %12.4f %5d/%d %9d/%d %14.3f\n", r.mode.c_str(), r.call_s, r.prepare_s, r.reused,
                    steps - 1, r.values_only, steps - 1, r.exchange_mb);
        out << '"' << r.mode << "\"," << cells * cells * cells << ',' << size << ',' << threads << ',' << steps << ','
            << r.call_s << ',' << r.prepare_s << ',' << r.reused << ',' << r.values_only << ',' << r.exchange_mb
            << '\n';
      }
      std::printf("wrote %s\n", csv.c_str());
    }
  }
  MPI_Finalize();
  return failed;
}
