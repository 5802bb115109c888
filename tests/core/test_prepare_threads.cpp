// prepare() keeps to options.threads, whatever arena its caller runs in: its passes over the
// field (the summary) and over a mesh (check, gather, sort, tables) run in a task arena of that
// width, never in the caller's wider one (a simulation that gives Tessera one thread must not
// find prepare on every core). Observed by the caller's arena: with threads = 1 no worker of it
// ever joins; with threads = 0 (the caller's width) its workers do, which shows that the
// observation sees prepare's work at all (a control that a loaded machine can leave
// inconclusive: a warning, not a failure; workers_can_join).
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "test_mesh_support.h"
#include "test_support.h"
#include "worker_count.h"

#include <cmath>
#include <thread>
#include <vector>

using tessera::Vec3;
using tessera_test::workers_joining;

namespace {

tessera::SceneDesc scene(int threads) {
  tessera::SceneDesc s;
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  s.camera.position = Vec3(0.5, 0.5, -2.0);
  s.camera.look_at = Vec3(0.5);
  s.image = {8, 8, 1, 0.0};
  s.options.threads = threads;
  return s;
}

}  // namespace

TEST_CASE("prepare keeps to options.threads, not the caller's arena", "[render][threads]") {
  const bool several_cores = std::thread::hardware_concurrency() > 1;
  if (!several_cores) WARN("one hardware thread: the control (workers join at threads 0) is not checked");

  SECTION("a field: the summary pass") {
    const int n = 160;  // 4 million voxels: the summary is split over many slabs
    const std::vector<float> data = tessera_test::blobby_field(n, n, n);
    const tessera::FieldView f = tessera::FieldView::contiguous(data.data(), tessera::DType::Float32, n, n, n);
    tessera::SceneDesc s = scene(1);
    s.geometry.spacing = Vec3(1.0 / (n - 1));
    CHECK(workers_joining([&] { (void)tessera::prepare(f, s); }) == 0);
    s.options.threads = 0;
    if (several_cores && !tessera_test::workers_can_join([&] { (void)tessera::prepare(f, s); }))
      WARN("no worker joined prepare at threads 0 in 5 tries (a loaded machine?): the control is inconclusive");
  }
  SECTION("a mesh: check, gather, sort and tables") {
    using namespace tessera_mesh_test;
    const int n = 48;  // 110 592 hexes: many chunks for every parallel pass
    const OwnedMesh om = one_domain(grid_hexes(
        n, n, n, Vec3(0.0), Vec3(1.0 / n), [](const Vec3& p) { return 0.5 + 0.5 * std::sin(7.0 * p.x) * p.y; },
        [](const Vec3& p) { return p; }));
    CHECK(workers_joining([&] { (void)tessera::prepare(om.mesh, scene(1)); }) == 0);
    if (several_cores && !tessera_test::workers_can_join([&] { (void)tessera::prepare(om.mesh, scene(0)); }))
      WARN("no worker joined prepare at threads 0 in 5 tries (a loaded machine?): the control is inconclusive");
  }
}
