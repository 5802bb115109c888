// tessera-heat's device solver (miniapp/src/heat_solver_cuda.cu) against the CPU solver
// (heat_solver.cpp): the same decomposition and sources, N steps of each, and the device's
// whole local array (ghost layers included, so the device halo exchange too) equal to the
// CPU's within 1e-12 relative (the only difference is the device's exp() in the source term).
// Also: the array is device memory (cudaPointerGetAttributes), each rank's device is its
// node-local rank modulo the visible devices, local_range and the time agree.
//
// Run under mpiexec -n 1, 2 and 4 (label gpu). Without a device every rank says why and exits
// with 77, which CTest reports as skipped (SKIP_RETURN_CODE, SKIP_REGULAR_EXPRESSION).
#include "cuda_device.h"
#include "heat_solver.h"
#include "heat_solver_cuda.h"

#include <cuda_runtime.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

int g_failures = 0;

void check(bool ok, const std::string& what) {
  if (ok) return;
  ++g_failures;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  std::fprintf(stderr, "FAILED (rank %d): %s\n", rank, what.c_str());
}

/// N steps of both solvers on `grid`; the whole local arrays compared after each step.
void compare(const heat::Index3& grid, int steps, const heat::CudaDeviceChoice& gpu) {
  heat::CartDecomposition decomp(MPI_COMM_WORLD, grid);
  heat::HeatParams params;
  params.sources = heat::demo_sources();
  heat::HeatSolver cpu(decomp, params);
  heat::CudaHeatSolver dev(decomp, params);
  const std::string where = "grid " + std::to_string(grid[0]) + "x" + std::to_string(grid[1]) + "x" +
                            std::to_string(grid[2]) + ", " + std::to_string(decomp.size()) + " rank(s)";

  // The published pointer is device memory of this rank's device, with the CPU's layout
  cudaPointerAttributes attr{};
  check(cudaPointerGetAttributes(&attr, dev.data()) == cudaSuccess && attr.type == cudaMemoryTypeDevice,
        where + ": data() is not device memory");
  check(attr.device == gpu.device && dev.device() == gpu.device, where + ": the array is not on the selected device");
  check(dev.array_dims() == cpu.array_dims(), where + ": array dims differ");
  check(dev.stable_dt() == cpu.stable_dt(), where + ": stable_dt differs");

  const double dt = cpu.stable_dt();
  const std::size_t total = static_cast<std::size_t>(cpu.array_dims()[0] * cpu.array_dims()[1] * cpu.array_dims()[2]);
  for (int s = 0; s <= steps; ++s) {
    if (s > 0) {
      cpu.step(dt);
      dev.step(dt);
    }
    // The whole array: owned vertices, and ghosts filled by the halo exchange
    const std::vector<double> d = dev.array_values();
    double worst = 0.0;
    std::size_t worst_at = 0;
    for (std::size_t e = 0; e < total; ++e) {
      const double c = cpu.data()[e];
      const double rel = std::abs(d[e] - c) / std::max(std::abs(c), 1.0);
      if (!(rel <= worst)) {  // (a NaN counts as the worst)
        worst = std::isnan(rel) ? INFINITY : rel;
        worst_at = e;
      }
    }
    check(worst <= 1e-12, where + ", step " + std::to_string(s) + ": element " + std::to_string(worst_at) +
                              " differs by " + std::to_string(worst) + " relative (device " +
                              std::to_string(d[worst_at]) + ", CPU " + std::to_string(cpu.data()[worst_at]) + ")");
  }
  check(dev.time() == cpu.time() && dev.steps() == cpu.steps(), where + ": time or step count differs");
  const auto [clo, chi] = cpu.local_range();
  const auto [dlo, dhi] = dev.local_range();
  check(std::abs(dlo - clo) <= 1e-12 * std::abs(clo) && std::abs(dhi - chi) <= 1e-12 * std::abs(chi),
        where + ": local_range differs");
  // Somewhere, not on every rank: a rank far from the sources stays cold for a few steps
  double hottest = chi;
  MPI_Allreduce(MPI_IN_PLACE, &hottest, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  check(hottest > params.initial_value + 1e-3, where + ": the sources heated nothing (the test compares too little)");
  const std::vector<double> owned = dev.owned_values(), owned_cpu = cpu.owned_values();
  check(owned.size() == owned_cpu.size(), where + ": owned_values sizes differ");
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);

  // A device on every rank, or skipped on every rank
  const heat::CudaDeviceChoice gpu = heat::select_cuda_device(MPI_COMM_WORLD);
  int ok = gpu.error.empty() ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (!ok) {
    if (rank == 0)
      std::printf("SKIPPED: the device heat solver's tests need a CUDA device on every rank: %s\n",
                  gpu.error.empty() ? "another rank has none" : gpu.error.c_str());
    MPI_Finalize();
    return 77;
  }
  // One device per rank: the node-local rank modulo the visible devices
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int local = 0;
  MPI_Comm_rank(node, &local);
  MPI_Comm_free(&node);
  check(gpu.device == local % gpu.visible, "device " + std::to_string(gpu.device) + " for node-local rank " +
                                               std::to_string(local) + " of " + std::to_string(gpu.visible) +
                                               " devices");

  try {
    compare({17, 13, 11}, 12, gpu);  // uneven axes: every rank count cuts them unevenly
    compare({24, 24, 24}, 6, gpu);
    compare({3, 5, 40}, 4, gpu);  // one interior vertex across i; many ranks along k
  } catch (const std::exception& e) {
    check(false, std::string("threw: ") + e.what());
  }

  int failures = g_failures;
  MPI_Allreduce(MPI_IN_PLACE, &failures, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  if (rank == 0)
    std::printf("%s: device heat solver against the CPU's, %d failure(s)\n", failures ? "FAILED" : "passed", failures);
  MPI_Finalize();
  return failures ? 1 : 0;
}
