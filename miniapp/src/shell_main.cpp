// tessera-heat-shell: the heat equation on a cylindrical shell, a curvilinear mesh, rendered
// in situ every step the config asks for (docs/miniapp.md, "A curvilinear mesh: the
// cylindrical shell").
//
//   [mpirun -n P] tessera-heat-shell [--config FILE] [--steps N] [--grid NR NTHETA NZ] [--output-dir DIR]
//
// The simulation: shell_solver.h, its columns of angles split over the ranks by
// ring_decomposition.h. Each rank publishes its block of cells as one curvilinear domain
// (shell_publish.h) through tessera_execute_mesh_domains, seen through <tessera/adapter.h>.
#include "ring_decomposition.h"
#include "shell_options.h"
#include "shell_publish.h"
#include "shell_solver.h"

#include <tessera/adapter.h>

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void say(int rank, const std::string& line, FILE* to = stdout) {
  if (rank != 0) return;
  std::fprintf(to, "%s\n", line.c_str());
  std::fflush(to);
}

double slowest(double local) {
  double max = 0.0;
  MPI_Reduce(&local, &max, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  return max;
}

int run(int argc, char** argv) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);

  heat::ShellOptions opt;
  try {
    opt = heat::parse_shell_options(argc, argv);
  } catch (const std::exception& e) {
    say(rank, std::string("tessera-heat-shell: ") + e.what() + "\n" + heat::shell_usage(), stderr);
    return 2;
  }
  if (opt.help) {
    say(rank, heat::shell_usage());
    return 0;
  }
  const std::string config = opt.config.empty() ? heat::default_shell_config_path() : opt.config;
  if (config.empty()) {
    say(rank, "tessera-heat-shell: cannot find the default config configs/heat_shell.yaml (give --config FILE)",
        stderr);
    return 1;
  }

  // Simulation: the shell, its columns of angles over the ranks, the demo's sources
  heat::ShellGeometry geometry;
  geometry.n_r = opt.grid[0];
  geometry.n_theta = opt.grid[1];
  geometry.n_z = opt.grid[2];
  std::unique_ptr<heat::RingDecomposition> ring;
  std::unique_ptr<heat::ShellSolver> solver;
  try {
    ring = std::make_unique<heat::RingDecomposition>(MPI_COMM_WORLD, geometry.n_theta);
    solver = std::make_unique<heat::ShellSolver>(*ring, heat::shell_demo_params(geometry));
  } catch (const std::exception& e) {  // same arguments everywhere: every rank fails alike
    say(rank, std::string("tessera-heat-shell: ") + e.what(), stderr);
    return 2;
  }
  const double dt = solver->stable_dt();
  say(rank, "tessera-heat-shell: " + std::to_string(opt.grid[0]) + "x" + std::to_string(opt.grid[1]) + "x" +
                std::to_string(opt.grid[2]) + " vertices (r x theta x z) on " + std::to_string(size) +
                " rank(s), dt = " + std::to_string(dt) + " s, " + std::to_string(opt.steps) + " steps, config " +
                config + (opt.output_dir ? ", output dir " + *opt.output_dir : std::string()));

  // Adapter: open collectively over the world communicator; --output-dir replaces the config's
  tessera::insitu::Adapter adapter;
  tessera::insitu::OpenOptions open_options;
  if (opt.output_dir) open_options.output_dir = *opt.output_dir;
  try {
    if (adapter.open(config, MPI_Comm_c2f(MPI_COMM_WORLD), open_options) != TESSERA_OK) {
      say(rank, "tessera-heat-shell: " + adapter.last_error(), stderr);
      return 1;
    }
  } catch (const tessera::insitu::AdapterError& e) {
    say(rank, std::string("tessera-heat-shell: ") + e.what(), stderr);
    return 1;
  }

  // The published block: this rank's cells as one curvilinear domain
  heat::ShellBlock block(geometry, ring->offset(), ring->owned());
  double sim_seconds = 0.0, render_seconds = 0.0;
  int renders = 0, failures = 0;
  const std::int64_t report_every = opt.steps >= 10 ? opt.steps / 10 : 1;
  for (std::int64_t step = 0; step <= opt.steps; ++step) {
    if (step > 0) {
      const auto t0 = Clock::now();
      solver->step(dt);
      sim_seconds += seconds_since(t0);
    }
    // Publish (the domain points into this step's array); every rank gets the same status
    const auto t0 = Clock::now();
    tessera_status status = TESSERA_OK;
    try {
      const tessera_mesh_domain& domain = block.domain(*solver, "temperature");
      status = adapter.execute_mesh_domains(step, solver->time(), {&domain, 1}, step == opt.steps);
    } catch (const tessera::insitu::AdapterError& e) {  // on_error: abort
      say(rank, "tessera-heat-shell: step " + std::to_string(step) + ": " + e.what() + " (on_error: abort; stopping)",
          stderr);
      return 1;
    }
    render_seconds += seconds_since(t0);
    renders += static_cast<int>(adapter.last_results().size());
    if (status != TESSERA_OK) {
      ++failures;
      say(rank,
          "tessera-heat-shell: step " + std::to_string(step) + ": " + adapter.last_error() +
              " (the simulation goes on)",
          stderr);
    }
    // Progress: temperature range and the slowest rank's seconds so far
    if (step % report_every == 0 || step == opt.steps) {
      const auto [lo, hi] = solver->local_range();
      double range[2] = {lo, -hi}, global[2];
      MPI_Reduce(range, global, 2, MPI_DOUBLE, MPI_MIN, 0, MPI_COMM_WORLD);
      const double sim = slowest(sim_seconds), ren = slowest(render_seconds);
      char line[256];
      std::snprintf(line, sizeof line,
                    "step %6lld  t = %.4f s  T in [%.2f, %.2f] K  simulation %.2f s  rendering %.2f s",
                    static_cast<long long>(step), solver->time(), global[0], -global[1], sim, ren);
      say(rank, line);
    }
  }
  adapter.close();

  const double sim = slowest(sim_seconds), ren = slowest(render_seconds);
  char line[256];
  std::snprintf(line, sizeof line,
                "tessera-heat-shell: %lld steps, %d renders (%d failed calls): simulation %.2f s, rendering %.2f s",
                static_cast<long long>(opt.steps), renders, failures, sim, ren);
  say(rank, line);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  int rc = 1;
  try {
    rc = run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-heat-shell: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return rc;
}
