// Robustness tests: see CMakeLists.txt in this folder.
// Messages stay short whatever the input: values echoed in config errors are cut to 64
// characters with "..." and their full length, long numbers are shown through format_number,
// control characters are escaped, and keys in key paths are cut the same way.
#include <catch2/catch.hpp>

#include "loading_support.h"

#include <string>

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using tessera_test::TempDir;
using namespace tessera_test::loading;

namespace {

constexpr std::size_t kShortMessage = 400;  ///< longer than any message the schema writes

}  // namespace

TEST_CASE("long string values are cut in messages", "[robustness][messages]") {
  const std::string big(1'000'000, 'x');
  // A plain scalar where a word is expected
  std::string e = config_error("renders:\n  - name: a\n    camera: {position: [0, 0, 5]}\n"
                               "    transfer_function: {opacity: [[0, 1]]}\n"
                               "    output: {tonemap: " +
                               big + "}\n");
  CHECK(e.size() < kShortMessage);
  CHECK_THAT(e, StartsWith("scene.yaml:5:14: renders[0].output.tonemap: " + std::string(64, 'x') +
                           "... (1000000 characters) is not allowed (allowed: aces, reinhard or "
                           "clamp)"));
  // A quoted string
  e = config_error("renders:\n  - name: \"" + big + "!\"\n");
  CHECK(e.size() < kShortMessage);
  CHECK_THAT(e, Contains("\"" + std::string(64, 'x') + "\"... (1000001 characters) is not a valid name"));
  // A render name of valid characters but absurd length: it would name files and every log line
  e = config_error("renders:\n  - name: " + big + "\n");
  CHECK(e.size() < kShortMessage);
  CHECK_THAT(e, Contains("(1000000 characters) is not a valid name (allowed: 1 to 128 letters"));
  // A file name: paths are cut to their first and last 100 characters
  e = config_error("volume: {file: " + big +
                   ", dims: [1, 1, 1], dtype: uint8}\n"
                   "renders:\n" +
                   minimal_render());
  CHECK(e.size() < 200 + kShortMessage);
  CHECK_THAT(e, Contains("...") && Contains(" characters)"));
  // An output pattern
  e = config_error("renders:\n" + minimal_render() + "    output: {file: \"{" + big + "}\"}\n");
  CHECK(e.size() < kShortMessage);
  // A field name: refused at load (it would be echoed by every data error at render time)
  e = config_error("renders:\n" + minimal_render() + "    field: " + big + "\n");
  CHECK(e.size() < kShortMessage);
  CHECK_THAT(e, StartsWith("scene.yaml:6:5: renders[0].field: " + std::string(64, 'x') +
                           "... (1000000 characters) is not a field name"));
  // An unknown key: the key path is cut too
  e = config_error("tessera:\n  ? " + big + "\n  : 1\n");
  CHECK(e.size() < kShortMessage);
  CHECK_THAT(e,
             StartsWith("scene.yaml:2:5: tessera." + std::string(64, 'x') + "... (1000000 characters): unknown key"));
}

TEST_CASE("long numbers are shown short", "[robustness][messages]") {
  const std::string digits300 = "1" + std::string(299, '0');
  // A double out of range
  std::string e = config_error("renders:\n  - name: a\n    camera: {position: [0, 0, 5], fov: " + digits300 + "}\n");
  CHECK(e.size() < kShortMessage);
  CHECK_THAT(e, Contains("renders[0].camera.fov: 1e+299 (written with 300 characters) is out of "
                         "range (0, 180)"));
  // An integer beyond 64 bits is out of range, not "not an integer"
  e = config_error("renders:\n  - name: a\n    image: {spp: " + digits300 + "}\n");
  CHECK(e.size() < kShortMessage);
  CHECK_THAT(e, Contains("renders[0].image.spp: 1e+299 (written with 300 characters) is out of "
                         "range [1, 1048576]"));
  // Short numbers are echoed as written
  e = config_error("renders:\n  - name: a\n    image: {spp: 0}\n");
  CHECK_THAT(e, Contains("renders[0].image.spp: 0 is out of range [1, 1048576]"));
}

TEST_CASE("control characters are escaped in messages", "[robustness][messages]") {
  const std::string e = config_error("renders:\n  - name: \"a\\0b\\x1bc\"\n");
  CHECK_THAT(e, Contains("\"a\\x00b\\x1bc\" is not a valid name"));
}

#ifdef TESSERA_RENDER_EXE
TEST_CASE("the command line cuts long arguments in messages", "[robustness][messages]") {
  TempDir dir;
  const Run r = run_cli(dir, "x.yaml --spp " + std::string(5000, '9'), "", 60);
  CHECK(r.status == 1);
  CHECK(r.err.size() < kShortMessage);
  CHECK_THAT(r.err, Contains("--spp: \"" + std::string(64, '9') + "... (5000 characters)\""));
}
#endif
