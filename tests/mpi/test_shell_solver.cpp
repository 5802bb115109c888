// tessera-heat-shell's solver (miniapp/src/shell_solver.cpp) and mesh (shell_geometry.cpp):
// one Bessel-Fourier mode of the cylindrical shell decays at the analytic rate with
// second-order convergence, a run over the ranks is bit-identical to one rank's, the ring's
// ghost columns hold the neighbours' columns, and the published blocks are closed,
// positively oriented and meet on the seam with column 0's coordinates bit for bit.
#include "ring_decomposition.h"
#include "shell_geometry.h"
#include "shell_solver.h"

#include "mpi_test_support.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

using namespace tessera_mpi_test;
using heat::RingDecomposition;
using heat::ShellGeometry;
using heat::ShellParams;
using heat::ShellSolver;

namespace {

constexpr double kPi = std::numbers::pi;

/// R(r) = J_m(lambda r) Y_m(lambda r0) - J_m(lambda r0) Y_m(lambda r), zero at r0 and, for the
/// lambda of first_root, at r1.
double radial(int m, double lambda, double r0, double r) {
  return std::cyl_bessel_j(m, lambda * r) * std::cyl_neumann(m, lambda * r0) -
         std::cyl_bessel_j(m, lambda * r0) * std::cyl_neumann(m, lambda * r);
}

/// The smallest lambda > 0 with R(r1) = 0: a scan for the first sign change, then bisection.
double first_root(int m, double r0, double r1) {
  double lo = 0.1;
  while (radial(m, lo, r0, r1) * radial(m, lo + 0.01, r0, r1) > 0.0) lo += 0.01;
  double hi = lo + 0.01;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (radial(m, lo, r0, r1) * radial(m, mid, r0, r1) <= 0.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Max over vertices of |T - T_exact| / (decay max|R|) for the mode R(r) cos(m theta)
/// sin(pi z / h), walls at 0, at t_end, on the grid n_r x n_theta x n_z over all ranks.
double mode_error(std::int64_t n_r, std::int64_t n_theta, std::int64_t n_z, double t_end) {
  constexpr int m = 2;
  ShellParams p;
  p.geometry.n_r = n_r;
  p.geometry.n_theta = n_theta;
  p.geometry.n_z = n_z;
  p.alpha = 1.0;
  p.wall_value = p.inner_value = p.outer_value = 0.0;
  const ShellGeometry& g = p.geometry;
  const double lambda = first_root(m, g.r0, g.r1);
  double r_max = 0.0;
  for (int s = 0; s <= 1000; ++s) r_max = std::max(r_max, std::fabs(radial(m, lambda, g.r0, g.r0 + s * 0.5e-3)));
  const auto mode = [&](double r, double theta, double z) {
    return radial(m, lambda, g.r0, r) * std::cos(m * theta) * std::sin(kPi * z / g.height);
  };
  RingDecomposition ring(MPI_COMM_WORLD, n_theta);
  ShellSolver s(ring, p);
  s.set_initial(mode);
  // Whole steps that land exactly on t_end, each within the stable limit
  const int steps = static_cast<int>(std::ceil(t_end / s.stable_dt()));
  for (int i = 0; i < steps; ++i) s.step(t_end / steps);
  const double decay = std::exp(-p.alpha * (lambda * lambda + kPi * kPi / (g.height * g.height)) * s.time());
  double err = 0.0;
  for (std::int64_t j = 0; j < ring.owned(); ++j)
    for (std::int64_t i = 0; i < n_r; ++i)
      for (std::int64_t k = 0; k < n_z; ++k) {
        const double exact = decay * mode(g.radius(i), g.theta(ring.offset() + j), g.z(k));
        err = std::max(err, std::fabs(s.at(i, j, k) - exact) / (decay * r_max));
      }
  double global = 0.0;
  MPI_Allreduce(&err, &global, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return global;
}

/// The demo run's owned columns of every rank, concatenated in rank order on rank 0 (the
/// columns are contiguous and the ranks hold them in order: the global array).
std::vector<double> run_demo(MPI_Comm comm, const ShellGeometry& geometry, int steps, double* t_end) {
  RingDecomposition ring(comm, geometry.n_theta);
  ShellSolver s(ring, heat::shell_demo_params(geometry));
  for (int i = 0; i < steps; ++i) s.step(s.stable_dt());
  *t_end = s.time();
  const int mine = static_cast<int>(ring.owned() * s.column_size());
  std::vector<int> counts(static_cast<std::size_t>(ring.size())), displs(counts.size());
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, ring.comm());
  for (std::size_t r = 1; r < counts.size(); ++r) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<double> global(ring.rank() == 0 ? static_cast<std::size_t>(geometry.n_theta * s.column_size()) : 0);
  MPI_Gatherv(s.data() + s.column_size(), mine, MPI_DOUBLE, global.data(), counts.data(), displs.data(), MPI_DOUBLE, 0,
              ring.comm());
  return global;
}

}  // namespace

TEST_CASE("a Bessel-Fourier mode of the shell decays at its analytic rate, second order in h",
          "[mpi][heat_shell][analytic]") {
  // R(r) cos(2 theta) sin(pi z / h) vanishes on every wall and is an eigenmode of the
  // Laplacian with eigenvalue -(lambda^2 + pi^2 / h^2). The scheme's error is O(h^2) + O(dt) =
  // O(h^2) as dt ~ h^2: halving every spacing must cut it by about 4 (asserted: by more than 3).
  constexpr double t_end = 0.02;  // the mode decays to about exp(-1)
  const double e1 = mode_error(9, 16, 9, t_end);
  const double e2 = mode_error(17, 32, 17, t_end);
  const double e3 = mode_error(33, 64, 33, t_end);
  INFO("relative max errors: " << e1 << ", " << e2 << ", " << e3);
  CHECK(e3 < 5e-3);
  CHECK(e1 / e2 > 3.0);
  CHECK(e2 / e3 > 3.0);
}

TEST_CASE("the shell run over the ranks is bit-identical to one rank's", "[mpi][heat_shell]") {
  ShellGeometry g;
  g.n_r = 9;
  g.n_theta = 23;
  g.n_z = 11;
  constexpr int kSteps = 30;
  double t_serial = 0.0, t_parallel = 0.0;
  std::vector<double> serial;
  {
    FirstRanks one(1);
    if (one.member()) serial = run_demo(one.comm(), g, kSteps, &t_serial);
  }
  const std::vector<double> parallel = run_demo(MPI_COMM_WORLD, g, kSteps, &t_parallel);
  bool ok = true;
  if (world_rank() == 0) {
    double max_rise = 0.0;
    for (double v : serial) max_rise = std::max(max_rise, v - 330.0);
    INFO("ranks " << world_size() << ", the sources' heating above the warmest wall " << max_rise << " K");
    CHECK(serial == parallel);
    CHECK(max_rise > 1.0);
    CHECK(t_serial == t_parallel);
    ok = serial == parallel && max_rise > 1.0 && t_serial == t_parallel;
  }
  REQUIRE(all_ranks(ok));
}

TEST_CASE("the shell's time step is the documented limit, larger steps are refused", "[mpi][heat_shell]") {
  ShellParams p;
  p.geometry.n_theta = 16;
  p.alpha = 0.5;
  RingDecomposition ring(MPI_COMM_WORLD, p.geometry.n_theta);
  ShellSolver s(ring, p);
  const ShellGeometry& g = p.geometry;
  const double arc = (g.r0 + g.dr()) * g.dtheta();
  const double limit = 1.0 / (2.0 * p.alpha * (1.0 / (g.dr() * g.dr()) + 1.0 / (arc * arc) + 1.0 / (g.dz() * g.dz())));
  CHECK(s.stable_dt() == Approx(0.9 * limit).epsilon(1e-14));
  CHECK_THROWS_AS(s.step(1.01 * limit), std::invalid_argument);
  CHECK_THROWS_AS(s.step(0.0), std::invalid_argument);
  CHECK_THROWS_AS(RingDecomposition(MPI_COMM_WORLD, world_size() - 1), std::invalid_argument);
}

TEST_CASE("the ring's ghost columns hold the neighbours' columns, across the seam too", "[mpi][heat_shell]") {
  ShellParams p;
  p.geometry.n_r = 5;
  p.geometry.n_theta = 7;
  p.geometry.n_z = 4;
  RingDecomposition ring(MPI_COMM_WORLD, p.geometry.n_theta);
  ShellSolver s(ring, p);
  // Encode the column in the value (walls aside, which keep their values)
  const ShellGeometry& g = p.geometry;
  s.set_initial([&](double, double theta, double) { return 1000.0 + std::round(theta / g.dtheta()); });
  bool ok = true;
  for (std::int64_t j = -1; j <= ring.owned(); ++j) {
    const std::int64_t global = ((ring.offset() + j) % g.n_theta + g.n_theta) % g.n_theta;
    ok = ok && s.at(2, j, 1) == 1000.0 + static_cast<double>(global);
  }
  REQUIRE(all_ranks(ok));
  std::int64_t total = 0, mine = ring.owned();
  MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  REQUIRE(total == g.n_theta);
}

TEST_CASE("the published blocks are positively oriented and meet column 0 on the seam", "[mpi][heat_shell]") {
  ShellGeometry g;
  g.n_r = 4;
  g.n_theta = 10;
  g.n_z = 3;
  RingDecomposition ring(MPI_COMM_WORLD, g.n_theta);
  const heat::ShellCoordinates c = heat::shell_block_coordinates(g, ring.offset(), ring.owned() + 1);
  bool ok = c.x.size() == static_cast<std::size_t>(g.n_z * g.n_r * (ring.owned() + 1));
  // Each cell's corner Jacobian along (z, r, theta), the published logical order, is positive
  const auto at = [&](std::int64_t k, std::int64_t i, std::int64_t j) {
    const std::size_t v = static_cast<std::size_t>((j * g.n_r + i) * g.n_z + k);
    return std::array<double, 3>{c.x[v], c.y[v], c.z[v]};
  };
  for (std::int64_t j = 0; j < ring.owned(); ++j)
    for (std::int64_t i = 0; i + 1 < g.n_r; ++i)
      for (std::int64_t k = 0; k + 1 < g.n_z; ++k) {
        const auto p = at(k, i, j), a = at(k + 1, i, j), b = at(k, i + 1, j), d = at(k, i, j + 1);
        const double u[3] = {a[0] - p[0], a[1] - p[1], a[2] - p[2]}, v[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]},
                     w[3] = {d[0] - p[0], d[1] - p[1], d[2] - p[2]};
        const double det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                           u[2] * (v[0] * w[1] - v[1] * w[0]);
        ok = ok && det > 0.0;
      }
  // The last vertex column is the next rank's first (on the last rank: column 0, bit for bit)
  for (std::int64_t i = 0; i < g.n_r; ++i)
    for (std::int64_t k = 0; k < g.n_z; ++k)
      ok = ok && at(k, i, ring.owned()) == g.position(i, ring.offset() + ring.owned(), k);
  const bool last = ring.rank() == ring.size() - 1;
  if (last) ok = ok && g.position(1, g.n_theta, 2) == g.position(1, 0, 2);
  REQUIRE(all_ranks(ok));
}
