// tessera-heat --amr's refined levels (miniapp/src/amr_levels.cpp): boxes nest inside each
// other and the mesh, the ranks' shares tile each box exactly once, a linear field is
// reproduced at every fine element, fine elements on level-0 samples hold level 0's value
// bit for bit, and every element's value is the same bit for bit for any rank count.
#include "amr_levels.h"
#include "cart_decomposition.h"
#include "heat_solver.h"

#include "mpi_test_support.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <map>
#include <vector>

using namespace tessera_mpi_test;
using heat::AmrBox;
using heat::AmrLevels;
using heat::AmrPatch;
using heat::AmrSettings;
using heat::CartDecomposition;
using heat::HeatParams;
using heat::HeatSolver;
using heat::Index3;

namespace {

std::int64_t scale(int level, int ratio) {
  std::int64_t R = 1;
  for (int l = 0; l < level; ++l) R *= ratio;
  return R;
}

/// Elements of a box at a level: vertex data (hi - lo) R + 1 per axis, cell data (hi - lo) R.
std::int64_t box_elements(const AmrBox& b, std::int64_t R, bool cell) {
  std::int64_t n = 1;
  for (int a = 0; a < 3; ++a) n *= (b.hi[a] - b.lo[a]) * R + (cell ? 0 : 1);
  return n;
}

/// Every value of every patch, keyed by (level, global index).
std::map<std::array<std::int64_t, 4>, double> by_index(const std::vector<AmrPatch>& patches) {
  std::map<std::array<std::int64_t, 4>, double> m;
  for (const AmrPatch& p : patches) {
    std::size_t n = 0;
    for (std::int64_t k = 0; k < p.dims[2]; ++k)
      for (std::int64_t j = 0; j < p.dims[1]; ++j)
        for (std::int64_t i = 0; i < p.dims[0]; ++i)
          m[{p.level, p.offset[0] + i, p.offset[1] + j, p.offset[2] + k}] = p.values[n++];
  }
  return m;
}

}  // namespace

TEST_CASE("refined boxes nest in the mesh and in each other, and follow the source", "[heat][amr]") {
  const Index3 g{24, 20, 16};
  const std::array<double, 3> h{1.0 / 23, 1.0 / 19, 1.0 / 15};
  for (bool cell : {false, true}) {
    // A centre inside, one near a corner (clipped) and one outside the mesh (still a box)
    for (const std::array<double, 3>& c : {std::array<double, 3>{0.5, 0.4, 0.6}, std::array<double, 3>{0.02, 0.97, 0.5},
                                           std::array<double, 3>{-0.5, 1.5, 0.5}}) {
      const std::vector<AmrBox> boxes = heat::refined_boxes(g, h, cell, c, {0.15, 0.075});
      REQUIRE(boxes.size() == 2);
      for (int a = 0; a < 3; ++a) {
        const std::int64_t top = cell ? g[a] : g[a] - 1;
        CHECK(0 <= boxes[0].lo[a]);
        CHECK(boxes[0].lo[a] < boxes[0].hi[a]);
        CHECK(boxes[0].hi[a] <= top);
        CHECK(boxes[0].lo[a] <= boxes[1].lo[a]);
        CHECK(boxes[1].lo[a] < boxes[1].hi[a]);
        CHECK(boxes[1].hi[a] <= boxes[0].hi[a]);
      }
    }
    // Inside the mesh, the box spans the centre +- the half-width (rounded outward)
    const std::vector<AmrBox> b = heat::refined_boxes(g, h, cell, {0.5, 0.5, 0.5}, {0.15});
    for (int a = 0; a < 3; ++a) {
      const double shift = cell ? 0.5 : 0.0;  // cell i spans [(i - 0.5) h, (i + 0.5) h]
      CHECK((static_cast<double>(b[0].lo[a]) - shift) * h[a] <= 0.35);
      CHECK((static_cast<double>(b[0].lo[a]) + 1 - shift) * h[a] > 0.35);
      CHECK((static_cast<double>(b[0].hi[a]) - shift) * h[a] >= 0.65);
      CHECK((static_cast<double>(b[0].hi[a]) - 1 - shift) * h[a] < 0.65);
    }
  }
}

TEST_CASE("the ranks' shares of a level tile its box exactly once", "[mpi][heat][amr]") {
  const Index3 g{23, 17, 19};
  CartDecomposition d(MPI_COMM_WORLD, g);
  const AmrBox box{{2, 0, 5}, {15, 16, 18}};
  for (bool cell : {false, true})
    for (int ratio : {2, 4}) {
      Index3 off{}, dims{};
      heat::rank_share(box, ratio, cell, d.offset(), d.owned(), off, dims);
      std::int64_t mine = dims[0] > 0 && dims[1] > 0 && dims[2] > 0 ? dims[0] * dims[1] * dims[2] : 0;
      std::int64_t total = 0;
      MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
      INFO("cell " << cell << " ratio " << ratio);
      CHECK(total == box_elements(box, ratio, cell));
      // (and each share lies in the box: with the sum, the shares cannot overlap)
      if (mine > 0)
        for (int a = 0; a < 3; ++a) {
          CHECK(off[a] >= box.lo[a] * ratio);
          CHECK(off[a] + dims[a] <= box.hi[a] * ratio + (cell ? 0 : 1));
        }
    }
}

TEST_CASE("a linear temperature is reproduced at every fine element", "[mpi][heat][amr][analytic]") {
  const Index3 g{21, 21, 21};
  CartDecomposition d(MPI_COMM_WORLD, g);
  HeatParams params;  // no sources: the fine levels hold I_0[T] alone
  HeatSolver solver(d, params);
  const auto f = [](double x, double y, double z) { return 300.0 + 40.0 * x - 25.0 * y + 10.0 * z; };
  solver.set_initial(f);
  heat::HeatSource followed;
  followed.centre = {0.5, 0.45, 0.55};  // boxes away from the walls (which hold 300 K)
  followed.sigma = 0.05;
  for (bool cell : {false, true})
    for (int ratio : {2, 4}) {
      AmrSettings s;
      s.levels = 3;
      s.ratio = ratio;
      s.cell = cell;
      AmrLevels amr(d, params, s, followed);
      amr.update(solver);
      double worst = 0.0;
      for (const AmrPatch& p : amr.patches()) {
        const double R = static_cast<double>(scale(p.level, ratio));
        std::size_t n = 0;
        for (std::int64_t k = 0; k < p.dims[2]; ++k)
          for (std::int64_t j = 0; j < p.dims[1]; ++j)
            for (std::int64_t i = 0; i < p.dims[0]; ++i) {
              const auto pos = [&](std::int64_t e, int a) {
                return (cell ? (static_cast<double>(e) + 0.5) / R - 0.5 : static_cast<double>(e) / R) *
                       solver.spacing()[a];
              };
              const double want = f(pos(p.offset[0] + i, 0), pos(p.offset[1] + j, 1), pos(p.offset[2] + k, 2));
              worst = std::max(worst, std::abs(p.values[n++] - want));
            }
      }
      INFO("cell " << cell << " ratio " << ratio << ": max |fine - linear| = " << worst << " K");
      CHECK(worst < 1e-10);
    }
}

TEST_CASE("fine values are level 0's on its samples and the same for any rank count", "[mpi][heat][amr]") {
  const Index3 g{25, 23, 21};
  HeatParams params;
  params.sources = heat::demo_sources();
  CartDecomposition world(MPI_COMM_WORLD, g), self(MPI_COMM_SELF, g);
  HeatSolver ws(world, params), ss(self, params);
  const double dt = ws.stable_dt();
  for (int s = 0; s < 12; ++s) {
    ws.step(dt);
    ss.step(dt);
  }
  for (bool cell : {false, true}) {
    AmrSettings settings;
    settings.levels = 3;
    settings.cell = cell;
    AmrLevels wa(world, params, settings, params.sources.front());
    AmrLevels sa(self, params, settings, params.sources.front());
    wa.update(ws);
    sa.update(ss);
    const auto all = by_index(sa.patches());
    std::int64_t compared = 0, differ = 0, samples = 0, off_sample = 0;
    for (const auto& [key, v] : by_index(wa.patches())) {
      const auto it = all.find(key);
      REQUIRE(it != all.end());
      ++compared;
      differ += std::memcmp(&v, &it->second, sizeof v) != 0 ? 1 : 0;
      // Vertex data: an element on a level-0 vertex holds the solver's value there
      const std::int64_t R = scale(static_cast<int>(key[0]), settings.ratio);
      if (!cell && key[1] % R == 0 && key[2] % R == 0 && key[3] % R == 0) {
        const Index3 o = world.offset();
        const std::int64_t i = key[1] / R - o[0], j = key[2] / R - o[1], k = key[3] / R - o[2];
        if (i < world.owned()[0] && j < world.owned()[1] && k < world.owned()[2]) {
          ++samples;
          off_sample += v != ws.at(i, j, k) ? 1 : 0;
        }
      }
    }
    INFO("cell " << cell << ": " << compared << " elements compared, " << samples << " on level-0 vertices");
    CHECK(differ == 0);
    CHECK(off_sample == 0);
    std::int64_t total = compared;
    MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
    CHECK(static_cast<std::size_t>(total) == all.size());
  }
}
