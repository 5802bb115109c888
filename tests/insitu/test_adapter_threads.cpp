// tessera.threads bounds the whole render pass, not only the tile render: the adapter's own
// passes over the data (here the value range of `range: auto`) and prepare's run within that
// many threads whatever arena the simulation calls from. Observed by the caller's arena: with
// `threads: 1` no worker of it joins the call; with `threads: 0` (the caller's width) its
// workers do, which shows that the observation sees the call's work at all (a control that a
// loaded machine can leave inconclusive: a warning, not a failure).
#include "insitu_test_support.h"
#include "worker_count.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <string>
#include <thread>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;

namespace {

/// Worker threads of a fresh arena (as wide as the machine) that joined an execute call made
/// from it, under
/// `tessera.threads: threads`.
int workers_joining(int threads, const std::vector<float>& values, int n) {
  TempDir dir;
  Adapter adapter;
  adapter.set_quiet(true);
  const std::string yaml = "tessera:\n  output_dir: " + dir.file("out") + "\n  threads: " + std::to_string(threads) +
                           "\nrenders:\n" + render_yaml("main", "", "", "density", 16, 1);
  REQUIRE(adapter.open(dir.write("a.yaml", yaml)) == TESSERA_OK);
  const tessera_field f = dense_field("density", values.data(), n);
  tessera_status status = TESSERA_OK;
  const int joined = tessera_test::workers_joining([&] { status = adapter.execute(1, 0.0, unit_grid(n), {&f, 1}); });
  INFO(adapter.last_error());
  REQUIRE(status == TESSERA_OK);
  return joined;
}

}  // namespace

TEST_CASE("adapter: tessera.threads bounds the whole pass, not only the tile render", "[insitu][threads]") {
  const int n = 128;  // 2 million values: the range pass is split over many slabs
  const std::vector<float> values = to_float(blob_values(n));
  CHECK(workers_joining(1, values, n) == 0);
  if (std::thread::hardware_concurrency() < 2) {
    WARN("one hardware thread: the control (workers join at threads 0) is not checked");
    return;
  }
  bool joined = false;
  for (int t = 0; t < 5 && !joined; ++t) joined = workers_joining(0, values, n) > 0;
  if (!joined)
    WARN("no worker joined the call at threads 0 in 5 tries (a loaded machine?): the control is inconclusive");
}
