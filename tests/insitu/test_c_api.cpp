// The C API from C (c_api_smoke.c is compiled as C99) and the C boundary's guarantees.
#include "insitu_test_support.h"

#include <tessera/config/config.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <filesystem>

namespace fs = std::filesystem;
using namespace tessera::insitu::test;

extern "C" int tessera_c_api_smoke(const char* yaml_path, const char* output_dir, int steps, char* err,
                                   std::size_t errlen);

TEST_CASE("C API: a C simulation with a ghosted float64 field", "[insitu][c-api]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string cfg =
      dir.write("a.yaml", config_yaml(out, render_yaml("heat", "{every: 2}", "", "temperature", 16, 1)));
  char err[1024] = "";
  REQUIRE(tessera_c_api_smoke(cfg.c_str(), nullptr, 5, err, sizeof err) == TESSERA_OK);
  CHECK(fs::exists(out + "/heat_0000.exr"));
  CHECK(fs::exists(out + "/heat_0002.exr"));
  CHECK(fs::exists(out + "/heat_0004.exr"));
  CHECK_FALSE(fs::exists(out + "/heat_0001.exr"));
  CHECK(fs::exists(out + "/tessera_effective_config.yaml"));
}

TEST_CASE("C API: errors come back from C as status and message", "[insitu][c-api]") {
  TempDir dir;
  const std::string cfg =
      dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("heat", "", "", "pressure", 16, 1)));
  char err[1024] = "";
  CHECK(tessera_c_api_smoke(cfg.c_str(), nullptr, 1, err, sizeof err) == TESSERA_ERROR_DATA);
  CHECK_THAT(std::string(err), Catch::Contains("pressure") && Catch::Contains("unknown"));
  CHECK(tessera_c_api_smoke(dir.file("none.yaml").c_str(), nullptr, 1, err, sizeof err) == TESSERA_ERROR_CONFIG);
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

TEST_CASE("C API: tessera_open_with_output_dir puts every output under the override", "[insitu][c-api]") {
  TempDir dir;
  const std::string config_out = dir.file("config_out");
  const std::string override_out = dir.file("override");
  const std::string cfg =
      dir.write("a.yaml", config_yaml(config_out, render_yaml("heat", "{every: 2}", "", "temperature", 16, 1)));
  char err[1024] = "";
  REQUIRE(tessera_c_api_smoke(cfg.c_str(), override_out.c_str(), 3, err, sizeof err) == TESSERA_OK);
  CHECK(fs::exists(override_out + "/heat_0000.exr"));
  CHECK(fs::exists(override_out + "/heat_0002.exr"));
  CHECK_FALSE(fs::exists(override_out + "/heat_0001.exr"));
  const std::string effective = override_out + "/tessera_effective_config.yaml";
  REQUIRE(fs::exists(effective));
  CHECK(tessera::config::load_config(effective).global.output_dir == override_out);
  CHECK_FALSE(fs::exists(config_out));

  // NULL and "" keep the config's output_dir
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open_with_output_dir(cfg.c_str(), -1, nullptr, &a) == TESSERA_OK);
  tessera_close(a);
  CHECK(fs::exists(config_out + "/tessera_effective_config.yaml"));
  fs::remove_all(config_out);
  REQUIRE(tessera_open_with_output_dir(cfg.c_str(), -1, "", &a) == TESSERA_OK);
  tessera_close(a);
  CHECK(fs::exists(config_out + "/tessera_effective_config.yaml"));
}

TEST_CASE("C API: tessera_open_with_output_dir fails as tessera_open does", "[insitu][c-api]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "")));
  const std::string override_out = dir.file("override");
  tessera_adapter* a = reinterpret_cast<tessera_adapter*>(&a);  // must be reset to NULL

  // Config errors: *out NULL, the message from tessera_last_error(NULL), nothing created
  CHECK(tessera_open_with_output_dir(dir.file("none.yaml").c_str(), -1, override_out.c_str(), &a) ==
        TESSERA_ERROR_CONFIG);
  CHECK(a == nullptr);
  CHECK_THAT(std::string(tessera_last_error(nullptr)), Catch::Contains("none.yaml"));
  CHECK(tessera_open_with_output_dir(nullptr, -1, override_out.c_str(), &a) == TESSERA_ERROR_CONFIG);
  CHECK(tessera_open_with_output_dir(cfg.c_str(), -1, override_out.c_str(), nullptr) == TESSERA_ERROR_CONFIG);
  CHECK_THAT(std::string(tessera_last_error(nullptr)), Catch::Contains("out is NULL"));
  CHECK_FALSE(fs::exists(override_out));

  // An override that cannot be created: TESSERA_ERROR_IO
  dir.write("file_in_the_way", "x");
  a = reinterpret_cast<tessera_adapter*>(&a);
  CHECK(tessera_open_with_output_dir(cfg.c_str(), -1, dir.file("file_in_the_way/out").c_str(), &a) == TESSERA_ERROR_IO);
  CHECK(a == nullptr);
  CHECK_THAT(std::string(tessera_last_error(nullptr)), Catch::Contains("file_in_the_way"));

  // A good open clears the thread's error
  REQUIRE(tessera_open_with_output_dir(cfg.c_str(), -1, override_out.c_str(), &a) == TESSERA_OK);
  CHECK(std::string(tessera_last_error(nullptr)).empty());
  CHECK(fs::exists(override_out + "/tessera_effective_config.yaml"));
  tessera_close(a);
}

TEST_CASE("C API: tessera_execute_refused fails what fires with the binding's reason, reading nothing",
          "[insitu][c-api]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string cfg = dir.write("a.yaml", config_yaml(out, render_yaml("r", "{every: 2}", "", "density", 8, 1)));
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  const char* reason = "mesh%refinement has 1 ratio(s); nlevels = 3 needs 2";
  // A render fires: it fails with the reason itself, for either call it stands for
  for (int domains_call = 0; domains_call < 2; ++domains_call) {
    CHECK(tessera_execute_refused(a, 0, 0.0, domains_call, 0, reason) == TESSERA_ERROR_DATA);
    CHECK(std::string(tessera_last_error(a)) == std::string("render 'r' at step 0: ") + reason);
  }
  // Nothing fires: nothing fails; the final form fires everything only with render_final_step
  CHECK(tessera_execute_refused(a, 1, 0.0, 1, 0, reason) == TESSERA_OK);
  CHECK(tessera_execute_refused(a, 3, 0.0, 1, 1, reason) == TESSERA_OK);
  // NULL or "": a generic reason, never a complaint about missing descriptors
  CHECK(tessera_execute_refused(a, 4, 0.0, 1, 0, nullptr) == TESSERA_ERROR_DATA);
  CHECK_THAT(std::string(tessera_last_error(a)), Catch::Contains("binding refused"));
  CHECK_FALSE(fs::exists(out + "/r_0000.exr"));
  tessera_close(a);
  CHECK(tessera_execute_refused(a, 0, 0.0, 1, 0, reason) == TESSERA_ERROR_CONFIG);
  CHECK_THAT(std::string(tessera_last_error(a)), Catch::Contains("closed"));
}
