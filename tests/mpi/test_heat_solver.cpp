// The heat miniapp's solver (miniapp/src/heat_solver.cpp): the decomposed run equals the
// serial one, one Fourier mode decays at the analytic rate with second-order convergence, the
// time step is the documented stable one, and halos hold the neighbours' values.
#include "cart_decomposition.h"
#include "field_dump.h"
#include "heat_solver.h"

#include "mpi_test_support.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <sys/resource.h>
#include <unistd.h>
#include <vector>

using namespace tessera_mpi_test;
using heat::CartDecomposition;
using heat::HeatParams;
using heat::HeatSolver;
using heat::Index3;

namespace {

/// The owned vertices of every rank, as one global C-order array on rank 0 of `comm`.
std::vector<double> gather_global(const CartDecomposition& d, const HeatSolver& s) {
  const Index3& n = d.owned();
  const Index3& g = d.global_dims();
  std::vector<double> mine;
  mine.reserve(static_cast<std::size_t>(n[0] * n[1] * n[2]));
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i) mine.push_back(s.at(i, j, k));
  std::int64_t box[6] = {d.offset()[0], d.offset()[1], d.offset()[2], n[0], n[1], n[2]};
  std::vector<std::int64_t> boxes(6 * static_cast<std::size_t>(d.size()));
  MPI_Gather(box, 6, MPI_INT64_T, boxes.data(), 6, MPI_INT64_T, 0, d.comm());
  std::vector<int> counts(d.size()), displs(d.size());
  for (int r = 0, at = 0; r < d.size(); ++r) {
    counts[r] = static_cast<int>(boxes[6 * r + 3] * boxes[6 * r + 4] * boxes[6 * r + 5]);
    displs[r] = at;
    at += counts[r];
  }
  std::vector<double> packed(d.rank() == 0 ? static_cast<std::size_t>(g[0] * g[1] * g[2]) : 0);
  MPI_Gatherv(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, packed.data(), counts.data(), displs.data(),
              MPI_DOUBLE, 0, d.comm());
  if (d.rank() != 0) return {};
  std::vector<double> global(packed.size());
  for (int r = 0; r < d.size(); ++r) {
    const std::int64_t* b = &boxes[6 * r];
    std::size_t at = static_cast<std::size_t>(displs[r]);
    for (std::int64_t k = 0; k < b[5]; ++k)
      for (std::int64_t j = 0; j < b[4]; ++j)
        for (std::int64_t i = 0; i < b[3]; ++i)
          global[static_cast<std::size_t>(((b[2] + k) * g[1] + b[1] + j) * g[0] + b[0] + i)] = packed[at++];
  }
  return global;
}

std::vector<double> run_demo(MPI_Comm comm, const Index3& grid, int steps, double* t_end) {
  CartDecomposition d(comm, grid);
  HeatParams p;
  p.sources = heat::demo_sources();
  HeatSolver s(d, p);
  for (int i = 0; i < steps; ++i) s.step(s.stable_dt());
  *t_end = s.time();
  return gather_global(d, s);
}

/// Max over vertices of |T - T_exact| / T_exact(centre) for the mode sin(pi x) sin(pi y)
/// sin(pi z) at t_end, on an n^3 grid over all ranks.
double fourier_error(int n, double alpha, double t_end) {
  CartDecomposition d(MPI_COMM_WORLD, {n, n, n});
  HeatParams p;
  p.alpha = alpha;
  p.boundary_value = 0.0;
  HeatSolver s(d, p);
  constexpr double pi = std::numbers::pi;
  const auto mode = [](double x, double y, double z) { return std::sin(pi * x) * std::sin(pi * y) * std::sin(pi * z); };
  s.set_initial(mode);
  // Whole steps that land exactly on t_end, each within the stable limit
  const int steps = static_cast<int>(std::ceil(t_end / s.stable_dt()));
  const double dt = t_end / steps;
  for (int i = 0; i < steps; ++i) s.step(dt);
  const double decay = std::exp(-3.0 * pi * pi * alpha * s.time());
  double err = 0.0;
  const Index3& o = d.offset();
  const Index3& m = d.owned();
  const auto& h = s.spacing();
  for (std::int64_t k = 0; k < m[2]; ++k)
    for (std::int64_t j = 0; j < m[1]; ++j)
      for (std::int64_t i = 0; i < m[0]; ++i) {
        const double exact = decay * mode((o[0] + i) * h[0], (o[1] + j) * h[1], (o[2] + k) * h[2]);
        err = std::max(err, std::fabs(s.at(i, j, k) - exact) / decay);
      }
  double global = 0.0;
  MPI_Allreduce(&err, &global, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return global;
}

}  // namespace

TEST_CASE("the decomposed heat solver matches the serial run", "[mpi][heat]") {
  const Index3 grid{21, 18, 15};
  constexpr int kSteps = 40;
  double t_serial = 0.0, t_parallel = 0.0;
  std::vector<double> serial;
  {
    FirstRanks one(1);
    if (one.member()) serial = run_demo(one.comm(), grid, kSteps, &t_serial);
  }
  const std::vector<double> parallel = run_demo(MPI_COMM_WORLD, grid, kSteps, &t_parallel);
  bool ok = true;
  if (world_rank() == 0) {
    double max_diff = 0.0, max_rise = 0.0;
    for (std::size_t v = 0; v < serial.size(); ++v) {
      max_diff = std::max(max_diff, std::fabs(serial[v] - parallel[v]));
      max_rise = std::max(max_rise, serial[v] - 300.0);
    }
    INFO("ranks " << world_size() << ": max |parallel - serial| = " << max_diff << " K");
    CHECK(max_diff < 1e-12);
    CHECK(max_rise > 1.0);  // the sources did heat the field
    CHECK(t_serial == t_parallel);
    ok = max_diff < 1e-12 && max_rise > 1.0 && t_serial == t_parallel;
  }
  REQUIRE(all_ranks(ok));
}

TEST_CASE("one Fourier mode decays as exp(-3 pi^2 alpha t), second order in h", "[mpi][heat][analytic]") {
  // sin(pi x) sin(pi y) sin(pi z) vanishes on the walls (Dirichlet 0) and is an eigenmode of
  // the Laplacian with eigenvalue -3 pi^2. The scheme's error is O(h^2) + O(dt) = O(h^2) as
  // dt ~ h^2: halving h must cut it by about 4 (asserted: by more than 3).
  constexpr double alpha = 1.0, t_end = 0.03;  // the mode decays to exp(-0.89) = 0.41
  const double e9 = fourier_error(9, alpha, t_end);
  const double e17 = fourier_error(17, alpha, t_end);
  const double e33 = fourier_error(33, alpha, t_end);
  INFO("relative max errors: h=1/8 " << e9 << ", h=1/16 " << e17 << ", h=1/32 " << e33);
  CHECK(e33 < 5e-3);
  CHECK(e9 / e17 > 3.0);
  CHECK(e17 / e33 > 3.0);
}

TEST_CASE("the time step is 0.9 h^2 / (6 alpha) on a cubic grid, larger steps are refused", "[mpi][heat]") {
  CartDecomposition d(MPI_COMM_WORLD, {17, 17, 17});
  HeatParams p;
  p.alpha = 0.5;
  HeatSolver s(d, p);
  const double h = 1.0 / 16.0;
  CHECK(s.stable_dt() == Approx(0.9 * h * h / (6.0 * p.alpha)).epsilon(1e-14));
  CHECK_THROWS_AS(s.step(1.01 * s.stable_dt() / 0.9), std::invalid_argument);
  CHECK_THROWS_AS(s.step(0.0), std::invalid_argument);
}

TEST_CASE("halo exchange fills every ghost that has a neighbour with the neighbour's value", "[mpi][heat]") {
  const Index3 g{13, 11, 9};
  CartDecomposition d(MPI_COMM_WORLD, g);
  HeatSolver s(d, HeatParams{});
  // Encode the global index in the value (walls aside, which keep the boundary value)
  const auto& h = s.spacing();
  const auto code = [&](double x, double y, double z) {
    return std::round(x / h[0]) + 100.0 * std::round(y / h[1]) + 10000.0 * std::round(z / h[2]);
  };
  s.set_initial(code);
  const Index3& n = s.array_dims();
  const Index3& o = d.offset();
  bool ok = true;
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i) {
        const std::int64_t gi = o[0] + i - 1, gj = o[1] + j - 1, gk = o[2] + k - 1;
        if (gi < 0 || gj < 0 || gk < 0 || gi >= g[0] || gj >= g[1] || gk >= g[2]) continue;  // outside
        const bool wall = gi == 0 || gj == 0 || gk == 0 || gi == g[0] - 1 || gj == g[1] - 1 || gk == g[2] - 1;
        const double expect = wall ? 300.0 : gi + 100.0 * gj + 10000.0 * gk;
        if (s.data()[static_cast<std::size_t>((k * n[1] + j) * n[0] + i)] != expect) ok = false;
      }
  REQUIRE(all_ranks(ok));
  // The owned blocks tile the grid exactly once
  std::int64_t mine = d.owned()[0] * d.owned()[1] * d.owned()[2], total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  REQUIRE(total == g[0] * g[1] * g[2]);
}

TEST_CASE("--dump writes the global field as raw float32, the same for any rank count", "[mpi][heat][dump]") {
  // The file name is agreed on rank 0 (one temp name per run, shared by all ranks).
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  char name[256] = {};
  if (rank == 0) std::snprintf(name, sizeof name, "/tmp/tessera_heat_dump_%d.raw", static_cast<int>(getpid()));
  MPI_Bcast(name, sizeof name, MPI_CHAR, 0, MPI_COMM_WORLD);
  const Index3 grid{13, 9, 7};
  CartDecomposition d(MPI_COMM_WORLD, grid);
  HeatParams p;
  p.sources = heat::demo_sources();
  HeatSolver s(d, p);
  for (int i = 0; i < 5; ++i) s.step(s.stable_dt());
  heat::dump_field(d, s, name);
  const std::vector<double> global = gather_global(d, s);
  if (rank == 0) {
    std::vector<float> file(global.size() + 1);
    FILE* f = std::fopen(name, "rb");
    REQUIRE(f != nullptr);
    const std::size_t got = std::fread(file.data(), sizeof(float), file.size(), f);
    std::fclose(f);
    CHECK(got == global.size());  // no more, no less
    bool same = true;
    for (std::size_t i = 0; i < global.size(); ++i) same = same && file[i] == static_cast<float>(global[i]);
    CHECK(same);
    CHECK(*std::max_element(global.begin(), global.end()) > p.initial_value);  // the sources heated it
    std::remove(name);
  }
  // An unwritable path fails on every rank with the file named, and nothing hangs.
  CHECK_THROWS_WITH(heat::dump_field(d, s, "/nonexistent_dir/x.raw"), Catch::Contains("/nonexistent_dir/x.raw"));
}

TEST_CASE("--dump under a file-size limit fails on every rank and keeps the older dump", "[mpi][heat][dump]") {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  char name[256] = {};
  if (rank == 0) std::snprintf(name, sizeof name, "/tmp/tessera_heat_dump_limit_%d.raw", static_cast<int>(getpid()));
  MPI_Bcast(name, sizeof name, MPI_CHAR, 0, MPI_COMM_WORLD);
  const std::string older = "an older, complete dump";
  if (rank == 0) {
    FILE* f = std::fopen(name, "wb");
    REQUIRE(f != nullptr);
    std::fwrite(older.data(), 1, older.size(), f);
    std::fclose(f);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  CartDecomposition d(MPI_COMM_WORLD, Index3{13, 9, 7});  // 3276 bytes
  HeatParams p;
  HeatSolver s(d, p);
  {
    // Each rank: at most 1000 bytes per file; SIGXFSZ ignored so the write fails with EFBIG
    rlimit old_limit{};
    getrlimit(RLIMIT_FSIZE, &old_limit);
    rlimit limit = old_limit;
    limit.rlim_cur = 1000;
    REQUIRE(setrlimit(RLIMIT_FSIZE, &limit) == 0);
    const sighandler_t old_action = std::signal(SIGXFSZ, SIG_IGN);
    CHECK_THROWS_WITH(heat::dump_field(d, s, name), Catch::Contains(name));
    setrlimit(RLIMIT_FSIZE, &old_limit);
    std::signal(SIGXFSZ, old_action);
  }
  if (rank == 0) {
    std::string text(64, '\0');
    FILE* f = std::fopen(name, "rb");
    REQUIRE(f != nullptr);
    text.resize(std::fread(text.data(), 1, text.size(), f));
    std::fclose(f);
    CHECK(text == older);
    int temporaries = 0;
    for (const auto& e : std::filesystem::directory_iterator("/tmp"))
      if (e.path().string().rfind(std::string(name) + ".tmp", 0) == 0) ++temporaries;
    CHECK(temporaries == 0);
    std::remove(name);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}
