// tessera-heat: a 3D heat-equation miniapp that publishes its temperature field to the
// Tessera in situ adapter every step (docs/miniapp.md).
//
//   [mpirun -n P] tessera-heat [--config FILE] [--steps N] [--grid NX NY NZ] [--output-dir DIR] [--dump FILE]
//                              [--work-ms N] [--domains-per-rank N] [--cell] [--amr [--levels L] [--ratio R]]
//                              [--device cpu|cuda]
//
// The simulation: heat_solver.h, or with --device cuda heat_solver_cuda.h on one GPU per rank
// (cuda_device.h), the field then published as a device pointer (docs/miniapp_gpu.md). The
// domain split and halo exchange: cart_decomposition.h, halo_exchange.h. The refined levels
// of --amr: amr_levels.h. The adapter is used only through its public header
// <tessera/adapter.h>.
#include "amr_levels.h"
#include "amr_publish.h"
#include "busy_work.h"
#include "cart_decomposition.h"
#include "cli_options.h"
#include "cuda_device.h"
#include "domain_split.h"
#include "field_dump.h"
#include "heat_solver.h"

#include <tessera/adapter.h>

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Everything rank 0 prints goes through here (one line, flushed).
void say(int rank, const std::string& line, FILE* to = stdout) {
  if (rank != 0) return;
  std::fprintf(to, "%s\n", line.c_str());
  std::fflush(to);
}

/// Max over ranks, on rank 0.
double slowest(double local) {
  double max = 0.0;
  MPI_Reduce(&local, &max, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  return max;
}

int run(int argc, char** argv) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);

  heat::Options opt;
  try {
    opt = heat::parse_options(argc, argv);
  } catch (const std::exception& e) {
    say(rank, std::string("tessera-heat: ") + e.what() + "\n" + heat::usage(), stderr);
    return 2;
  }
  if (opt.help) {
    say(rank, heat::usage());
    return 0;
  }
  // --device cuda: every rank needs a GPU before the run starts (the ranks agree)
  const bool on_gpu = opt.device == heat::Device::cuda;
  std::string device_text = "on the CPU";
  if (on_gpu) {
    if (!heat::cuda_built()) {
      say(rank, "tessera-heat: --device cuda: " + heat::select_cuda_device(MPI_COMM_WORLD).error, stderr);
      return 1;
    }
    const heat::CudaDeviceChoice gpu = heat::select_cuda_device(MPI_COMM_WORLD);
    int ok = gpu.error.empty() ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (!gpu.error.empty()) {
      std::fprintf(stderr, "tessera-heat: --device cuda: rank %d: %s\n", rank, gpu.error.c_str());
      return 1;
    }
    if (!ok) {
      say(rank, "tessera-heat: --device cuda: another rank has no usable CUDA device", stderr);
      return 1;
    }
    device_text = "on CUDA device " + std::to_string(gpu.device) + " of " + std::to_string(gpu.visible) + " (" +
                  gpu.name + ") on rank 0, the field in device memory";
  }

  const std::string config = opt.config.empty() ? heat::default_config_path() : opt.config;
  if (config.empty()) {
    say(rank, "tessera-heat: cannot find the default config configs/heat.yaml (give --config FILE)", stderr);
    return 1;
  }

  // Simulation: decomposition, solver with the demo's moving heat sources
  heat::HeatParams params;
  params.sources = heat::demo_sources();
  std::unique_ptr<heat::CartDecomposition> decomp;
  std::unique_ptr<heat::HeatSimulation> solver;
  const heat::HeatSolver* host_solver = nullptr;  // the CPU solver (--amr reads its array)
  try {
    decomp = std::make_unique<heat::CartDecomposition>(MPI_COMM_WORLD, opt.grid);
    if (on_gpu) {
      solver = heat::make_cuda_solver(*decomp, params);
    } else {
      auto cpu = std::make_unique<heat::HeatSolver>(*decomp, params);
      host_solver = cpu.get();
      solver = std::move(cpu);
    }
  } catch (const std::invalid_argument& e) {  // same arguments everywhere: every rank fails alike
    say(rank, std::string("tessera-heat: ") + e.what(), stderr);
    return 2;
  } catch (const std::exception& e) {  // a device's failure, agreed by the ranks: each says its own
    std::fprintf(stderr, "tessera-heat: rank %d: %s\n", rank, e.what());
    return 1;
  }
  const double dt = solver->stable_dt();
  say(rank, "tessera-heat: " + std::to_string(opt.grid[0]) + "x" + std::to_string(opt.grid[1]) + "x" +
                std::to_string(opt.grid[2]) + " vertices on " + std::to_string(size) + " rank(s) (" +
                std::to_string(decomp->procs()[0]) + "x" + std::to_string(decomp->procs()[1]) + "x" +
                std::to_string(decomp->procs()[2]) + "), dt = " + std::to_string(dt) + " s, " +
                std::to_string(opt.steps) + " steps" +
                (opt.work_ms > 0 ? " (+" + std::to_string(opt.work_ms) + " ms of work each)" : std::string()) + ", " +
                device_text + ", config " + config +
                (opt.output_dir ? ", output dir " + *opt.output_dir : std::string()));

  // Adapter: open collectively over the world communicator; --output-dir replaces the config's
  tessera::insitu::Adapter adapter;
  tessera::insitu::OpenOptions open_options;
  if (opt.output_dir) open_options.output_dir = *opt.output_dir;
  try {
    if (adapter.open(config, MPI_Comm_c2f(MPI_COMM_WORLD), open_options) != TESSERA_OK) {
      say(rank, "tessera-heat: " + adapter.last_error(), stderr);
      return 1;
    }
  } catch (const tessera::insitu::AdapterError& e) {
    say(rank, std::string("tessera-heat: ") + e.what(), stderr);
    return 1;
  }

  // --device cuda: the adapter orders its reads of the device array after the solver's stream
  // (tessera_set_cuda_stream; step() also returns with that stream idle)
  if (on_gpu && adapter.set_cuda_stream(solver->cuda_stream()) != TESSERA_OK) {
    say(rank, "tessera-heat: " + adapter.last_error(), stderr);
    return 1;
  }

  // The published field: this rank's array, ghost layers included and declared as ghosts; with
  // --device cuda a device pointer of this rank's GPU, read in place by the adapter
  const heat::Index3& n = solver->array_dims();
  tessera_field field{};
  field.name = "temperature";
  field.dtype = TESSERA_FLOAT64;
  for (int a = 0; a < 3; ++a) {
    field.dims[a] = n[a];
    field.ghosts_lo[a] = 1;
    field.ghosts_hi[a] = 1;
  }
  field.byte_strides[0] = sizeof(double);
  field.byte_strides[1] = static_cast<std::int64_t>(sizeof(double)) * n[0];
  field.byte_strides[2] = static_cast<std::int64_t>(sizeof(double)) * n[0] * n[1];
  tessera_grid grid{};
  for (int a = 0; a < 3; ++a) {
    grid.origin[a] = 0.0;
    grid.spacing[a] = solver->spacing()[a];
    grid.global_dims[a] = opt.grid[a];
    grid.offset[a] = decomp->offset()[a];
  }
  // --domains-per-rank N: the same array as N uneven domains of the same mesh (zero copy);
  // --cell: published as cells centred on the vertices (one domain unless N says more);
  // --amr: level 0 as domains, and the refined levels around the first demo source
  if ((opt.cell || opt.amr) && opt.domains_per_rank == 0) opt.domains_per_rank = 1;
  std::unique_ptr<heat::AmrLevels> amr;
  std::vector<int> refinement;
  if (opt.amr) {
    heat::AmrSettings settings;
    settings.levels = opt.levels;
    settings.ratio = opt.ratio;
    settings.cell = opt.cell;
    amr = std::make_unique<heat::AmrLevels>(*decomp, params, settings, params.sources.front());
    refinement.assign(static_cast<std::size_t>(opt.levels - 1), opt.ratio);
    say(rank, "tessera-heat: --amr: " + std::to_string(opt.levels) + " levels, ratio " + std::to_string(opt.ratio) +
                  ", refined boxes follow the first heat source");
  }
  tessera_mesh mesh{};
  mesh.association = opt.cell ? TESSERA_CELL : TESSERA_VERTEX;
  mesh.nlevels = amr ? opt.levels : 1;
  mesh.refinement = amr ? refinement.data() : nullptr;
  for (int a = 0; a < 3; ++a) {
    mesh.origin[a] = opt.cell ? grid.origin[a] - 0.5 * grid.spacing[a] : grid.origin[a];
    mesh.spacing[a] = grid.spacing[a];
    mesh.global_dims[a] = grid.global_dims[a];
  }
  std::vector<tessera_field> domain_fields, amr_fields;
  std::vector<tessera_domain> domains;
  bool split_ok = true;
  std::string split_error;
  if (opt.domains_per_rank > 0) {
    try {
      field.data = solver->data();
      domains = heat::split_domains(field, {grid.offset[0], grid.offset[1], grid.offset[2]}, opt.domains_per_rank,
                                    domain_fields);
    } catch (const std::exception& e) {
      split_ok = false;
      split_error = e.what();
    }
    int all_ok = split_ok ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &all_ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (!all_ok) {
      say(rank, "tessera-heat: " + (split_ok ? std::string("a rank cannot cut its array") : split_error), stderr);
      return 2;
    }
  }

  double sim_seconds = 0.0, render_seconds = 0.0;
  int renders = 0, failures = 0, skipped = 0;
  // With a render budget: the budget, and the cost after the first call that rendered (whose
  // renders measure what a render costs, at min_spp, and may overspend)
  double budget = 0.0, sim_after_first = 0.0, render_after_first = 0.0;
  bool rendered_once = false;
  double work_sink = 0.0;
  const std::int64_t report_every = opt.steps >= 10 ? opt.steps / 10 : 1;
  for (std::int64_t step = 0; step <= opt.steps; ++step) {
    // Simulate (step 0 is the initial state)
    if (step > 0) {
      const auto t0 = Clock::now();
      solver->step(dt);
      work_sink += heat::busy_work(static_cast<double>(opt.work_ms));
      const double s = seconds_since(t0);
      sim_seconds += s;
      if (rendered_once) sim_after_first += s;
    }
    // --amr: re-grid around the source at this step's time and fill the fine levels from this
    // step's level 0 (simulation work: the adapter reads them only when a render fires)
    if (amr) {
      const auto ta = Clock::now();
      amr->update(*host_solver);
      const double s = seconds_since(ta);
      sim_seconds += s;
      if (rendered_once) sim_after_first += s;
    }
    // Publish; every rank gets the same status
    field.data = solver->data();
    const auto t0 = Clock::now();
    tessera_status status = TESSERA_OK;
    try {
      if (opt.domains_per_rank > 0) {
        // (the solver swaps its buffers: the domains point into this step's array)
        domains = heat::split_domains(field, {grid.offset[0], grid.offset[1], grid.offset[2]}, opt.domains_per_rank,
                                      domain_fields);
        if (amr) heat::append_amr_domains(amr->patches(), field, amr_fields, domains);
        status = adapter.execute_domains(step, solver->time(), mesh, domains, step == opt.steps);
      } else {
        status = adapter.execute(step, solver->time(), grid, {&field, 1}, step == opt.steps);
      }
    } catch (const tessera::insitu::AdapterError& e) {  // on_error: abort
      say(rank, "tessera-heat: step " + std::to_string(step) + ": " + e.what() + " (on_error: abort; stopping)",
          stderr);
      return 1;
    }
    const double r = seconds_since(t0);
    render_seconds += r;
    if (rendered_once) render_after_first += r;
    for (const tessera::insitu::RenderResult& res : adapter.last_results()) {
      budget = res.budget;
      ++(res.budget_skipped ? skipped : renders);
    }
    rendered_once = rendered_once || !adapter.last_results().empty();
    if (status != TESSERA_OK) {
      ++failures;
      say(rank,
          "tessera-heat: step " + std::to_string(step) + ": " + adapter.last_error() + " (the simulation goes on)",
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
  if (opt.dump) {
    try {
      heat::dump_field(*decomp, *solver, *opt.dump);
      say(rank, "tessera-heat: wrote " + *opt.dump + " (" + std::to_string(opt.grid[0]) + "x" +
                    std::to_string(opt.grid[1]) + "x" + std::to_string(opt.grid[2]) + " float32)");
    } catch (const std::exception& e) {
      say(rank, std::string("tessera-heat: ") + e.what(), stderr);
      return 1;
    }
  }

  const double sim = slowest(sim_seconds), ren = slowest(render_seconds);
  const double sim_after = slowest(sim_after_first), ren_after = slowest(render_after_first);
  char line[512];
  // The in situ cost: rendering (every execute call) against the simulation's own time, and
  // with a budget the budget, and the same ratio once the first renders have measured their cost
  char cost[192] = "";
  if (sim > 0.0 && budget > 0.0 && sim_after > 0.0)
    std::snprintf(cost, sizeof cost, " (%.3gx the simulation; budget %g, %.3gx after the first renders)", ren / sim,
                  budget, ren_after / sim_after);
  else if (sim > 0.0 && budget > 0.0)
    std::snprintf(cost, sizeof cost, " (%.3gx the simulation; budget %g)", ren / sim, budget);
  else if (sim > 0.0) std::snprintf(cost, sizeof cost, " (%.3gx the simulation)", ren / sim);
  char skips[64] = "";
  if (budget > 0.0) std::snprintf(skips, sizeof skips, ", %d skipped by the budget", skipped);
  std::snprintf(line, sizeof line,
                "tessera-heat: %lld steps, %d renders%s (%d failed calls): simulation %.2f s, rendering %.2f s%s",
                static_cast<long long>(opt.steps), renders, skips, failures, sim, ren, cost);
  say(rank, line);
  if (work_sink < 0.0) say(rank, "");  // (keeps the added work observable)
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
    std::fprintf(stderr, "tessera-heat: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return rc;
}
