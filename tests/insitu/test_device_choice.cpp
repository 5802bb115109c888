// The adapter's device choice (docs/gpu.md) where no GPU is needed: host data renders on the
// CPU under `auto` with no bytes copied; `device: cuda` without a usable GPU fails the render
// by name (never a crash) and the next render still runs; set_cuda_stream's handle rules.
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/cuda_render.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;

namespace {

constexpr int kN = 12;

void open_quiet(Adapter& adapter, const TempDir& dir, const std::string& renders, const std::string& global) {
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), renders, global));
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
}

}  // namespace

TEST_CASE("device auto and cpu: host data renders on the CPU, nothing copied", "[insitu][device]") {
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  for (const char* device : {"auto", "cpu"}) {
    INFO(device);
    TempDir dir;
    Adapter adapter;
    open_quiet(adapter, dir, render_yaml("main", ""), std::string("  device: ") + device + "\n");
    REQUIRE(adapter.execute(1, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);
    const RenderResult& r = adapter.last_results().at(0);
    CHECK(r.device == "cpu");
    CHECK(r.stats.bytes_to_device == 0);
    CHECK(r.stats.bytes_to_host == 0);
  }
}

TEST_CASE("device cuda without a usable GPU: the render fails by name, the adapter goes on", "[insitu][device]") {
  std::string why;
  if (tessera::cuda_device_count(&why) > 0) SUCCEED("a GPU is visible: tests/gpu_insitu covers this process");
  else {
    const std::vector<float> sim = to_float(blob_values(kN));
    const tessera_field field = dense_field("density", sim.data(), kN);
    TempDir dir;
    Adapter adapter;
    // on_error: warn (the default): the render fails, execute reports it, the next call runs
    open_quiet(adapter, dir, render_yaml("gpu", "") + render_yaml("cpu_one", ""), "  device: cuda\n");
    CHECK(adapter.execute(1, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_ERROR_RENDER);
    const RenderResult& r = adapter.last_results().at(0);
    CHECK(r.status == TESSERA_ERROR_RENDER);
    CHECK_THAT(r.error, Contains("render 'gpu'") && Contains("tessera.device is cuda"));
    if (!tessera::cuda_built()) CHECK_THAT(r.error, Contains("built without CUDA"));
    CHECK(adapter.execute(2, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_ERROR_RENDER);
  }
}

TEST_CASE("set_cuda_stream: kept on an open adapter, refused on a closed or NULL one", "[insitu][device]") {
  TempDir dir;
  Adapter adapter;
  CHECK(adapter.set_cuda_stream(nullptr) == TESSERA_ERROR_CONFIG);  // not open
  open_quiet(adapter, dir, render_yaml("main", ""), "");
  int fake_stream = 0;  // never dereferenced while no device array is read
  CHECK(adapter.set_cuda_stream(&fake_stream) == TESSERA_OK);
  CHECK(adapter.set_cuda_stream(nullptr) == TESSERA_OK);
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  CHECK(adapter.execute(1, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_OK);
  CHECK(adapter.close() == TESSERA_OK);
  CHECK(tessera_set_cuda_stream(nullptr, nullptr) == TESSERA_ERROR_CONFIG);
  CHECK_THAT(tessera_last_error(nullptr), Contains("tessera_set_cuda_stream"));
}
