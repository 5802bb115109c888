// The C API from C (c_api_smoke.c is compiled as C99) and the C boundary's guarantees.
#include "insitu_test_support.h"

#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <filesystem>

namespace fs = std::filesystem;
using namespace tessera::insitu::test;

extern "C" int tessera_c_api_smoke(const char* yaml_path, int steps, char* err, std::size_t errlen);

TEST_CASE("C API: a C simulation with a ghosted float64 field", "[insitu][c-api]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string cfg =
      dir.write("a.yaml", config_yaml(out, render_yaml("heat", "{every: 2}", "", "temperature", 16, 1)));
  char err[1024] = "";
  REQUIRE(tessera_c_api_smoke(cfg.c_str(), 5, err, sizeof err) == TESSERA_OK);
  CHECK(fs::exists(out + "/heat_0000.exr"));
  CHECK(fs::exists(out + "/heat_0002.exr"));
  CHECK(fs::exists(out + "/heat_0004.exr"));
  CHECK_FALSE(fs::exists(out + "/heat_0001.exr"));
  CHECK(fs::exists(out + "/tessera_effective_config.yaml"));
}

TEST_CASE("C API: errors come back from C as status and message", "[insitu][c-api]") {
  TempDir dir;
  const std::string cfg = dir.write(
      "a.yaml", config_yaml(dir.file("out"), render_yaml("heat", "", "", "pressure", 16, 1)));
  char err[1024] = "";
  CHECK(tessera_c_api_smoke(cfg.c_str(), 1, err, sizeof err) == TESSERA_ERROR_DATA);
  CHECK_THAT(std::string(err), Catch::Contains("pressure") && Catch::Contains("unknown"));
  CHECK(tessera_c_api_smoke(dir.file("none.yaml").c_str(), 1, err, sizeof err) == TESSERA_ERROR_CONFIG);
  CHECK_THAT(std::string(err), Catch::Contains("none.yaml"));
}

TEST_CASE("C API: tessera_last_error(NULL) is per thread and cleared by a good open", "[insitu][c-api]") {
  TempDir dir;
  tessera_adapter* a = nullptr;
  CHECK(tessera_open(nullptr, -1, &a) == TESSERA_ERROR_CONFIG);
  CHECK(std::string(tessera_last_error(nullptr)).size() > 0);
  CHECK(tessera_open("x.yaml", -1, nullptr) == TESSERA_ERROR_CONFIG);
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "")));
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  CHECK(std::string(tessera_last_error(nullptr)).empty());
  CHECK(std::string(tessera_last_error(a)).empty());
  tessera_close(a);
}
