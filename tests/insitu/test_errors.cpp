// Errors: broken configs and descriptors give the right status and a message that names the
// fault; failures inside rendering leave the simulation running; on_error warn / disable /
// abort.
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/image_io.h>

#include <catch2/catch.hpp>

#include <sys/mman.h>
#include <unistd.h>

#include <filesystem>
#include <limits>
#include <regex>

namespace fs = std::filesystem;
using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Contains;

namespace {

constexpr int kN = 8;

/// A camera whose up is parallel to its view direction: prepare() throws.
const char* kBadCamera = "    camera: {position: [0.5, 0.5, 4], look_at: center, up: [0, 0, 1]}\n";

std::string open_error(const std::string& yaml_path) {
  tessera_adapter* a = reinterpret_cast<tessera_adapter*>(0x1);
  const tessera_status s = tessera_open(yaml_path.c_str(), -1, &a);
  CHECK(s == TESSERA_ERROR_CONFIG);
  CHECK(a == nullptr);
  return tessera_last_error(nullptr);
}

}  // namespace

TEST_CASE("broken configs: TESSERA_ERROR_CONFIG naming file, line, column and key", "[insitu][errors]") {
  TempDir dir;
  SECTION("unknown key") {
    std::string yaml = config_yaml(dir.file("out"), render_yaml("r", "{every: 1}"));
    yaml.replace(yaml.find("fov: 40"), 7, "fox: 40");
    const std::string msg = open_error(dir.write("bad.yaml", yaml));
    CHECK_THAT(msg, Contains(dir.file("bad.yaml")));
    CHECK(std::regex_search(msg, std::regex(R"(bad\.yaml:\d+:\d+: )")));
    CHECK_THAT(msg, Contains("renders[0].camera"));
    CHECK_THAT(msg, Contains("fox"));
  }
  SECTION("value out of range") {
    const std::string yaml = config_yaml(dir.file("out"), render_yaml("r", "{every: 0}"));
    const std::string msg = open_error(dir.write("bad.yaml", yaml));
    CHECK(std::regex_search(msg, std::regex(R"(bad\.yaml:\d+:\d+: renders\[0\]\.trigger\.every)")));
  }
  SECTION("missing file") { CHECK_THAT(open_error(dir.file("missing.yaml")), Contains("missing.yaml")); }
  SECTION("YAML syntax") {
    const std::string msg = open_error(dir.write("bad.yaml", "renders: [ {name: x\n"));
    CHECK(std::regex_search(msg, std::regex(R"(bad\.yaml:\d+:\d+)")));
  }
  SECTION("an MPI communicator handle cannot be used") {
    // Without MPI any handle but -1 is refused; with MPI, a never-created handle is invalid
    const std::string yaml = dir.write("ok.yaml", config_yaml(dir.file("out"), render_yaml("r", "")));
    tessera_adapter* a = nullptr;
    CHECK(tessera_open(yaml.c_str(), 123456, &a) == TESSERA_ERROR_CONFIG);
    CHECK(a == nullptr);
    CHECK_THAT(std::string(tessera_last_error(nullptr)), Contains("123456"));
  }
  SECTION("C++ API, and nothing written for a failed open") {
    std::string yaml = config_yaml(dir.file("out"), render_yaml("r", ""));
    yaml += "bogus: 1\n";
    Adapter adapter;
    CHECK(adapter.open(dir.write("bad.yaml", yaml)) == TESSERA_ERROR_CONFIG);
    CHECK_THAT(adapter.last_error(), Contains("bogus"));
    CHECK_FALSE(adapter.is_open());
    CHECK_FALSE(fs::exists(dir.file("out")));
  }
  SECTION("output_dir cannot be created: TESSERA_ERROR_IO") {
    dir.write("file_in_the_way", "x");
    const std::string yaml = config_yaml(dir.file("file_in_the_way/out"), render_yaml("r", ""));
    Adapter adapter;
    CHECK(adapter.open(dir.write("a.yaml", yaml)) == TESSERA_ERROR_IO);
    CHECK_THAT(adapter.last_error(), Contains("file_in_the_way"));
  }
}

TEST_CASE("broken descriptors: TESSERA_ERROR_DATA naming the field and the fault", "[insitu][errors]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "{every: 1}")));
  const std::vector<float> sim = to_float(blob_values(kN));
  const std::vector<float> before = sim;
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);

  const auto data_error = [&](tessera_field f, tessera_grid g = unit_grid(kN)) {
    const tessera_status s = adapter.execute(0, 0.0, g, {&f, 1});
    CHECK(s == TESSERA_ERROR_DATA);
    REQUIRE(adapter.last_results().size() == 1);
    CHECK(adapter.last_results()[0].status == TESSERA_ERROR_DATA);
    return adapter.last_error();
  };
  const tessera_field good = dense_field("density", sim.data(), kN);
  tessera_field f = good;

  f.data = nullptr;
  CHECK_THAT(data_error(f), Contains("field 'density'") && Contains("null"));
  f = good;
  f.dims[1] = 0;
  CHECK_THAT(data_error(f), Contains("field 'density'") && Contains("dims[1]"));
  f = good;
  f.byte_strides[2] = 4 * kN;  // planes on top of rows
  CHECK_THAT(data_error(f), Contains("field 'density'") && Contains("overlap"));
  f = good;
  f.byte_strides[0] = 0;
  CHECK_THAT(data_error(f), Contains("field 'density'") && Contains("stride"));
  f = good;
  f.byte_strides[2] = std::numeric_limits<std::int64_t>::max() / 4;
  CHECK_THAT(data_error(f), Contains("field 'density'") && Contains("address space"));
  f = good;
  f.byte_strides[2] = -f.byte_strides[2];  // from the first element downwards past address 0?
  f.data = reinterpret_cast<const void*>(std::uintptr_t{64});
  CHECK_THAT(data_error(f), Contains("address space"));
  f = good;
  f.ghosts_lo[0] = 4;
  f.ghosts_hi[0] = 4;
  CHECK_THAT(data_error(f), Contains("field 'density'") && Contains("ghost"));
  f = good;
  f.ghosts_lo[2] = kN;
  CHECK_THAT(data_error(f), Contains("ghost"));
  f = good;
  f.ghosts_hi[1] = -1;
  CHECK_THAT(data_error(f), Contains("negative ghost"));
  f = good;
  f.dtype = static_cast<tessera_dtype>(7);
  CHECK_THAT(data_error(f), Contains("field 'density'") && Contains("dtype 7"));
  f = good;
  f.name = "temperature";
  CHECK_THAT(data_error(f), Contains("'density'") && Contains("unknown") && Contains("temperature"));

  tessera_grid g = unit_grid(kN);
  g.spacing[1] = 0.0;
  CHECK_THAT(data_error(good, g), Contains("field 'density'") && Contains("spacing[1]"));
  g = unit_grid(kN);
  g.spacing[2] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THAT(data_error(good, g), Contains("spacing[2]"));
  g = unit_grid(kN);
  g.origin[0] = std::numeric_limits<double>::infinity();
  CHECK_THAT(data_error(good, g), Contains("origin"));
  g = unit_grid(kN);
  g.global_dims[0] = kN - 1;  // real dims exceed the global grid
  CHECK_THAT(data_error(good, g), Contains("field 'density'") && Contains("global_dims"));
  g = unit_grid(kN);
  g.offset[2] = -1;
  CHECK_THAT(data_error(good, g), Contains("offset"));
  g = unit_grid(kN);
  g.global_dims[1] = kN + 4;  // one rank holding part of the grid
  CHECK_THAT(data_error(good, g), Contains("whole grid"));

  // C API: the field list and the grid themselves (the C++ adapter closed first: two open
  // adapters may not share an output_dir)
  adapter.close();
  tessera_adapter* c = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &c) == TESSERA_OK);
  const tessera_grid ug = unit_grid(kN);
  CHECK(tessera_execute(c, 0, 0.0, nullptr, &good, 1) == TESSERA_ERROR_DATA);
  CHECK_THAT(std::string(tessera_last_error(c)), Contains("grid"));
  CHECK(tessera_execute(c, 0, 0.0, &ug, nullptr, 1) == TESSERA_ERROR_DATA);
  CHECK_THAT(std::string(tessera_last_error(c)), Contains("NULL"));
  CHECK(tessera_execute(c, 0, 0.0, &ug, &good, -2) == TESSERA_ERROR_DATA);
  tessera_field unnamed = good;
  unnamed.name = nullptr;
  CHECK(tessera_execute(c, 0, 0.0, &ug, &unnamed, 1) == TESSERA_ERROR_DATA);
  CHECK_THAT(std::string(tessera_last_error(c)), Contains("name is null"));
  const tessera_field twice[2] = {good, good};
  CHECK(tessera_execute(c, 0, 0.0, &ug, twice, 2) == TESSERA_ERROR_DATA);
  CHECK_THAT(std::string(tessera_last_error(c)), Contains("twice"));
  // ... and a good call afterwards renders, clearing the error
  CHECK(tessera_execute(c, 0, 0.0, &ug, &good, 1) == TESSERA_OK);
  CHECK(std::string(tessera_last_error(c)).empty());
  CHECK(tessera_close(c) == TESSERA_OK);
  CHECK(tessera_close(nullptr) == TESSERA_OK);
  CHECK(tessera_execute(nullptr, 0, 0.0, &ug, &good, 1) != TESSERA_OK);

  CHECK(sim == before);  // the simulation's memory is only read
}

TEST_CASE("unreadable field memory: TESSERA_ERROR_DATA naming the field and the pointer, no fault",
          "[insitu][errors]") {
  // Freed (unmapped) memory, pages without host access (what a freed cudaMalloc pointer is on
  // the host), and an array running past the end of its mapping: each is found before any
  // value is read, and the next call with good memory renders
  constexpr int n = 16;  // 16 KiB of float32: several pages
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "{every: 1}")));
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  const std::size_t page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const std::size_t bytes = static_cast<std::size_t>(n) * n * n * sizeof(float);
  const std::size_t pages = (bytes + page - 1) / page;
  const auto data_error = [&](const void* p) {
    const tessera_field f = dense_field("density", static_cast<const float*>(p), n);
    CHECK(adapter.execute(0, 0.0, unit_grid(n), {&f, 1}) == TESSERA_ERROR_DATA);
    return adapter.last_error();
  };
  // Unmapped
  void* m = ::mmap(nullptr, pages * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  REQUIRE(m != MAP_FAILED);
  REQUIRE(::munmap(m, pages * page) == 0);
  CHECK_THAT(data_error(m), Contains("field 'density'") && Contains("not readable host memory") &&
                                Contains("byte 0 of the " + std::to_string(bytes) + " bytes"));
  // No access
  void* none = ::mmap(nullptr, pages * page, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  REQUIRE(none != MAP_FAILED);
  CHECK_THAT(data_error(none), Contains("not readable host memory"));
  ::munmap(none, pages * page);
  // Readable but one page short: the last byte is past the mapping
  void* shortm = ::mmap(nullptr, pages * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  REQUIRE(shortm != MAP_FAILED);
  REQUIRE(::munmap(static_cast<char*>(shortm) + (pages - 1) * page, page) == 0);
  REQUIRE(pages > 1);
  const std::string e = data_error(shortm);
  CHECK_THAT(e, Contains("not readable host memory"));
  std::smatch at;
  REQUIRE(std::regex_search(e, at, std::regex("byte ([0-9]+) of the")));
  CHECK(std::stoull(at[1].str()) >= (pages - 1) * page);  // a byte in the unmapped page
  CHECK(std::stoull(at[1].str()) < bytes);
  ::munmap(shortm, (pages - 1) * page);
  // The next call with good memory renders
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field good = dense_field("density", sim.data(), n);
  CHECK(adapter.execute(1, 0.0, unit_grid(n), {&good, 1}) == TESSERA_OK);
}

TEST_CASE("a failing render leaves the simulation running and the others rendering", "[insitu][errors]") {
  TempDir dir;
  const std::string renders = render_yaml("bad", "{every: 1}", kBadCamera) + render_yaml("good", "{every: 1}");
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), renders));
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  for (std::int64_t step = 0; step < 3; ++step) {
    CHECK(adapter.execute(step, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_ERROR_RENDER);
    CHECK_THAT(adapter.last_error(), Contains("render 'bad'") && Contains("parallel"));
    REQUIRE(adapter.last_results().size() == 2);
    CHECK(adapter.last_results()[0].status == TESSERA_ERROR_RENDER);
    CHECK(adapter.last_results()[0].files.empty());
    CHECK(adapter.last_results()[1].status == TESSERA_OK);
    CHECK(adapter.last_results()[1].files.size() == 1);
  }
  CHECK(adapter.last_image("bad") == nullptr);
  CHECK(adapter.last_image("good") != nullptr);
}

TEST_CASE("an envmap that disappears fails that step only", "[insitu][errors]") {
  TempDir dir;
  tessera::Image env;
  env.width = 8;
  env.height = 4;
  env.rgba.assign(8 * 4 * 4, 0.5f);
  const std::string env_path = dir.file("sky.exr");
  tessera::write_exr(env_path, env);
  const std::string extra = "    background: {type: envmap, file: sky.exr}\n";
  const std::string cfg = dir.write(
      "a.yaml", config_yaml(dir.file("out"), render_yaml("r", "", extra), "  on_error: disable\n  max_failures: 2\n"));
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);

  const auto run = [&](std::int64_t step) { return adapter.execute(step, 0.0, unit_grid(kN), {&field, 1}); };
  CHECK(run(0) == TESSERA_OK);
  fs::rename(env_path, env_path + ".away");
  CHECK(run(1) == TESSERA_ERROR_RENDER);
  CHECK_THAT(adapter.last_error(), Contains("sky.exr"));
  fs::rename(env_path + ".away", env_path);
  CHECK(run(2) == TESSERA_OK);  // and the success resets the failure count
  fs::rename(env_path, env_path + ".away");
  CHECK(run(3) == TESSERA_ERROR_RENDER);
  fs::rename(env_path + ".away", env_path);
  CHECK(run(4) == TESSERA_OK);
}

TEST_CASE("on_error: disable stops a render after max_failures consecutive failures", "[insitu][errors]") {
  TempDir dir;
  const std::string renders = render_yaml("bad", "", kBadCamera) + render_yaml("good", "{every: 2}");
  const std::string cfg =
      dir.write("a.yaml", config_yaml(dir.file("out"), renders, "  on_error: disable\n  max_failures: 3\n"));
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  const tessera_grid g = unit_grid(kN);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  for (int step = 0; step < 3; ++step) {
    CHECK(adapter.execute(step, 0.0, g, {&field, 1}) == TESSERA_ERROR_RENDER);
    CHECK(adapter.last_results().size() == (step % 2 == 0 ? 2u : 1u));
  }
  // `bad` is disabled; `good` goes on rendering, and the status says something was skipped
  CHECK(adapter.execute(3, 0.0, g, {&field, 1}) == TESSERA_ERROR_DISABLED);
  CHECK(adapter.last_results().empty());
  CHECK_THAT(adapter.last_error(), Contains("render 'bad'") && Contains("disabled after 3"));
  CHECK(adapter.execute(4, 0.0, g, {&field, 1}) == TESSERA_ERROR_DISABLED);
  REQUIRE(adapter.last_results().size() == 1);
  CHECK(adapter.last_results()[0].name == "good");
  CHECK(adapter.last_results()[0].status == TESSERA_OK);
}

TEST_CASE("on_error: disable with every render disabled: TESSERA_ERROR_DISABLED at once", "[insitu][errors]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("bad", "", kBadCamera),
                                                          "  on_error: disable\n  max_failures: 3\n"));
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  tessera_adapter* c = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &c) == TESSERA_OK);
  const tessera_grid g = unit_grid(kN);
  for (int step = 0; step < 3; ++step) CHECK(tessera_execute(c, step, 0.0, &g, &field, 1) == TESSERA_ERROR_RENDER);
  CHECK(tessera_execute(c, 3, 0.0, &g, &field, 1) == TESSERA_ERROR_DISABLED);
  CHECK_THAT(std::string(tessera_last_error(c)), Contains("disabled"));
  // Not even the descriptors are looked at any more
  CHECK(tessera_execute_final(c, 4, 0.0, nullptr, nullptr, 0) == TESSERA_ERROR_DISABLED);
  CHECK(tessera_close(c) == TESSERA_OK);
}

TEST_CASE("on_error: abort rethrows in C++ and keeps failing in C", "[insitu][errors]") {
  TempDir dir;
  const std::string renders = render_yaml("bad", "{every: 2}", kBadCamera) + render_yaml("good", "");
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), renders, "  on_error: abort\n"));
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  const tessera_grid g = unit_grid(kN);

  SECTION("C++") {
    Adapter adapter;
    adapter.set_quiet(true);
    REQUIRE(adapter.open(cfg) == TESSERA_OK);
    CHECK(adapter.execute(1, 0.0, g, {&field, 1}) == TESSERA_OK);  // only `good` fires
    try {
      adapter.execute(2, 0.0, g, {&field, 1});
      FAIL("no exception");
    } catch (const AdapterError& e) {
      CHECK(e.status() == TESSERA_ERROR_RENDER);
      CHECK_THAT(std::string(e.what()), Contains("render 'bad'"));
    }
    CHECK(adapter.last_results().size() == 1);  // the call stopped at the failure
    CHECK_THROWS_AS(adapter.execute(3, 0.0, g, {&field, 1}), AdapterError);
  }
  SECTION("C") {
    tessera_adapter* c = nullptr;
    REQUIRE(tessera_open(cfg.c_str(), -1, &c) == TESSERA_OK);
    CHECK(tessera_execute(c, 1, 0.0, &g, &field, 1) == TESSERA_OK);
    CHECK(tessera_execute(c, 2, 0.0, &g, &field, 1) == TESSERA_ERROR_RENDER);
    // Every later call returns the error without rendering, even where only `good` fires
    CHECK(tessera_execute(c, 3, 0.0, &g, &field, 1) == TESSERA_ERROR_RENDER);
    CHECK_THAT(std::string(tessera_last_error(c)), Contains("abort") && Contains("render 'bad'"));
    CHECK(tessera_close(c) == TESSERA_OK);
  }
}

TEST_CASE("on_error: warn never disables", "[insitu][errors]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("bad", "", kBadCamera)));
  const std::vector<float> sim = to_float(blob_values(kN));
  const tessera_field field = dense_field("density", sim.data(), kN);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  for (int step = 0; step < 5; ++step)  // never disabled: warn has no failure limit
    CHECK(adapter.execute(step, 0.0, unit_grid(kN), {&field, 1}) == TESSERA_ERROR_RENDER);
}
