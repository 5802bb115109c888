// Robustness tests: see CMakeLists.txt in this folder.
// Messages name the real fault and show user text safely: invisible characters (a BOM inside
// a file), invalid UTF-8 and control characters are escaped; paths are cut to their first and
// last parts (also in the adapter's runtime messages, however often they are quoted); custom
// YAML tags are refused at their line:column; output.file patterns stay inside output_dir and
// never write hidden files; data of one vertex under distance: fit, and flat data, are
// blamed on the data's extent, not on the camera.
#include <catch2/catch.hpp>

#include "insitu_test_support.h"
#include "loading_support.h"

#include <tessera/config/build_scene.h>
#include <tessera/config/output_path.h>
#include <tessera/message_text.h>
#include <tessera/tessera.h>

#include <string>

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using tessera_test::TempDir;
using tessera_test::loading::config_error;
using tessera_test::loading::load_error;
using tessera_test::loading::minimal_render;

namespace {

constexpr std::size_t kShortMessage = 600;  ///< longer than any message with a cut path
const std::string kBom = "\xEF\xBB\xBF";

}  // namespace

TEST_CASE("message text: invisible characters, invalid UTF-8 and controls are escaped, long text cut",
          "[robustness][messages]") {
  using tessera::printable_text;
  CHECK(printable_text("plain caf\xC3\xA9 \xE6\x97\xA5") == "plain caf\xC3\xA9 \xE6\x97\xA5");  // UTF-8 kept
  CHECK(printable_text(kBom + "key") == "\\u{FEFF}key");
  CHECK(printable_text("a\xE2\x80\x8B"
                       "b\xE2\x80\xAE"
                       "c") == "a\\u{200B}b\\u{202E}c");  // ZWSP, RLO
  CHECK(printable_text("a\xC2\x85"
                       "b") == "a\\u{0085}b");                                     // C1 control
  CHECK(printable_text("\xFF\xC3(\xED\xA0\x80") == "\\xff\\xc3(\\xed\\xa0\\x80");  // invalid, surrogate
  CHECK(printable_text("\xC0\xAF") == "\\xc0\\xaf");                               // overlong '/'
  CHECK(printable_text("a\x1b[31mb\tc\n") == "a\\x1b[31mb\\x09c\\x0a");
  CHECK(printable_text("l1\nl2", true) == "l1\nl2");

  CHECK(tessera::shown_value(std::string(100, 'x')) == std::string(64, 'x') + "... (100 characters)");
  // A cut never splits a UTF-8 character
  const std::string e_acute = "\xC3\xA9";
  std::string accents;
  for (int i = 0; i < 40; ++i) accents += e_acute;
  CHECK(tessera::shown_value(accents) == accents.substr(0, 64) + "... (80 characters)");
  CHECK(tessera::shown_value("x" + accents) == "x" + accents.substr(0, 62) + "... (81 characters)");

  const std::string path = "/scratch/" + std::string(5000, 'd') + "/image.png";
  const std::string shown = tessera::shown_path(path);
  CHECK(shown.size() < 260);
  CHECK_THAT(shown, StartsWith("/scratch/ddd") && Contains("ddd/image.png (5019 characters)"));

  // A message quoting a long path twice names it short twice
  const std::string msg = "cannot create '" + path + "': File name too long [" + path + "]";
  const std::string quoted = tessera::message_quoting(msg, path);
  CHECK(quoted.size() < 2 * 260 + 60);
  CHECK_THAT(quoted, StartsWith("cannot create '/scratch/ddd") && Contains("(5019 characters)': File name too long ["));
}

TEST_CASE("config: a BOM starts a file legally, one inside it and invalid UTF-8 show escaped",
          "[robustness][messages]") {
  // At the very start: legal YAML, accepted
  CHECK(config_error(kBom + "renders:\n" + minimal_render()) == "");
  // Inside a key: the unknown key is shown with the BOM visible
  std::string e = config_error("tessera:\n  thr" + kBom + "eads: 2\nrenders:\n" + minimal_render());
  CHECK_THAT(e, StartsWith("scene.yaml:2:3: tessera.thr\\u{FEFF}eads: unknown key"));
  // At the start of a later line (a file pasted together)
  e = config_error("renders:\n" + minimal_render() + kBom + "tessera: {threads: 2}\n");
  CHECK_THAT(e, Contains(": \\u{FEFF}tessera: unknown key"));
  // Invalid UTF-8 in a value
  e = config_error("renders:\n" + minimal_render() +
                   "    output: {tonemap: \"ac\xFF\xFE"
                   "es\"}\n");
  CHECK_THAT(e, Contains("\"ac\\xff\\xfees\" is not allowed"));
  CHECK(e.find('\xFF') == std::string::npos);
}

TEST_CASE("config: a string that is not UTF-8 is refused naming the byte (it could not be written back)",
          "[robustness][messages]") {
  // A field name, an output pattern and an output_dir with bytes that are no UTF-8: the
  // effective config's writer would turn them into other characters (found by fuzzing)
  std::string e = config_error("renders:\n" + minimal_render() + "    field: \"te\xFF\xFFmp\"\n");
  CHECK_THAT(e, Contains("renders[0].field") && Contains("is not valid UTF-8 (byte 0xFF at offset 2"));
  CHECK(e.find('\xFF') == std::string::npos);
  e = config_error("renders:\n" + minimal_render() + "    output: {file: \"a\xC3(\"}\n");
  CHECK_THAT(e, Contains("renders[0].output.file") && Contains("byte 0xC3 at offset 1"));
  e = config_error("tessera: {output_dir: \"out\xED\xA0\x80\"}\nrenders:\n" + minimal_render());  // a surrogate
  CHECK_THAT(e, Contains("tessera.output_dir") && Contains("byte 0xED at offset 3"));
  // Other scripts are fine
  CHECK(config_error("renders:\n" + minimal_render() + "    field: \"température_β\"\n") == "");
}

TEST_CASE("config: a long file name is cut to its first and last parts", "[robustness][messages]") {
  TempDir dir;
  const std::string missing = dir.file(std::string(4000, 'q') + "/scene.yaml");
  const std::string e = load_error(missing);
  INFO(e);
  CHECK(e.size() < kShortMessage);
  CHECK_THAT(e, Contains("qqq/scene.yaml (" + std::to_string(missing.size()) + " characters)"));
}

TEST_CASE("config: a custom YAML tag is an error at its line:column naming the tag", "[robustness][messages]") {
  std::string e =
      config_error("renders:\n  - name: !foo a\n" + minimal_render().substr(std::string("  - name: a\n").size()));
  CHECK_THAT(e, StartsWith("scene.yaml:2:11: YAML tag '!foo' is not supported"));
  e = config_error("tessera: {threads: !!binary AAAA}\nrenders:\n" + minimal_render());
  CHECK_THAT(e, StartsWith("scene.yaml:1:20: YAML tag '!!binary' is not supported"));
  e = config_error("tessera: !!map {threads: 2}\nrenders:\n" + minimal_render());
  CHECK_THAT(e, StartsWith("scene.yaml:1:10: YAML tag '!!map' is not supported"));
  // A '!' inside a value, or a quoted one, is no tag
  CHECK(config_error("renders:\n" + minimal_render() + "    output: {file: \"!{name}\"}\n") == "");
  CHECK(config_error("renders:\n" + minimal_render() + "    output: {file: a!b}\n") == "");
}

TEST_CASE("config: output.file stays inside output_dir and never names a hidden file", "[robustness][messages]") {
  struct Case {
    const char* pattern;
    const char* says;
  };
  const Case cases[] = {
      {".", "'.' component"},
      {"..", "'..' component"},
      {"../{name}", "'..' component, which would write outside output_dir"},
      {"a/../../{name}", "'..' component"},
      {"/tmp/{name}", "absolute path, which would write outside output_dir"},
      {".{name}", "hidden file name"},
      {"images/.{step}", "hidden file name"},
      {"a/./b", "'.' component"},
  };
  for (const Case& c : cases) {
    INFO(c.pattern);
    const std::string e = config_error("renders:\n" + minimal_render() + "    output: {file: \"" + c.pattern + "\"}\n");
    CHECK_THAT(e, StartsWith("scene.yaml:6:14: renders[0].output.file: bad output pattern") && Contains(c.says));
  }
  // Names below output_dir, dots inside names included, stay allowed
  for (const char* ok : {"images/{name}", "{name}.v2", "a..b", "{name}/s{step}", "x/{time:.2f}"}) {
    INFO(ok);
    CHECK(config_error("renders:\n" + minimal_render() + "    output: {file: \"" + ok + "\"}\n") == "");
  }
  // After substitution too: a name the caller passes (the library validates render names)
  using tessera::config::format_output_path;
  CHECK_THROWS_WITH(format_output_path("{name}", "..", 0, 0.0, 0), Contains("after formatting (gives \"..\")"));
  CHECK_THROWS_WITH(format_output_path("{name}/x", "/etc", 0, 0.0, 0), Contains("absolute path"));
  CHECK_THROWS_WITH(format_output_path("{name}", ".hidden", 0, 0.0, 0), Contains("hidden file name"));
}

TEST_CASE("tessera-render: output.file leaving output_dir is refused before anything is written",
          "[robustness][messages]") {
  TempDir dir;
  dir.write("v.raw", std::string(8 * 4, '\0'));
  dir.write("s.yaml", "volume: {file: v.raw, dims: [2, 2, 2], dtype: float32}\ntessera: {output_dir: out}\nrenders:\n" +
                          minimal_render() + "    output: {file: \"../escaped\"}\n");
  const tessera_test::CliRun r = tessera_test::run_cli(dir, "s.yaml");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Contains("renders[0].output.file: bad output pattern \"../escaped\": has a '..' component"));
  CHECK_FALSE(std::filesystem::exists(dir.path() / "escaped.exr"));
}

TEST_CASE("tessera-render: a 5000-character output_dir is not echoed in full", "[robustness][messages]") {
  TempDir dir;
  dir.write("v.raw", std::string(8 * 4, '\0'));
  const std::string long_dir = std::string(5000, 'o');
  dir.write("s.yaml", "volume: {file: v.raw, dims: [2, 2, 2], dtype: float32}\ntessera: {output_dir: " + long_dir +
                          "}\nrenders:\n  - name: a\n    image: {width: 4, height: 4, spp: 1}\n"
                          "    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}}\n"
                          "    transfer_function: {opacity: [[0, 0], [1, 1]]}\n");
  const tessera_test::CliRun r = tessera_test::run_cli(dir, "s.yaml");
  INFO(r.err);
  CHECK(r.status == 1);
  CHECK(r.err.size() < kShortMessage);
  CHECK_THAT(r.err, Contains("tessera-render: error: ") && Contains(" characters)"));
}

TEST_CASE("distance: fit on data of one vertex names the data's extent, not the camera", "[robustness][messages]") {
  const tessera::config::Config cfg = tessera::config::parse_config(
      "renders:\n  - name: a\n    image: {width: 4, height: 4, spp: 1}\n"
      "    camera: {position: {orbit: {azimuth: 0, elevation: 0, distance: fit}}, look_at: center}\n"
      "    transfer_function: {opacity: [[0, 0], [1, 1]]}\n",
      "scene.yaml", "");
  const tessera::config::RenderSpec& spec = cfg.renders.at(0);
  tessera::Bounds point;
  point.lo = point.hi = tessera::Vec3(2.0, 3.0, 4.0);
  try {
    tessera::config::build_scene(spec, point, {0.0, 1.0}, tessera::VolumeGeometry{});
    FAIL("no error");
  } catch (const std::invalid_argument& e) {
    CHECK_THAT(e.what(), Contains("camera.position: an orbit with distance: fit is measured in the data's "
                                  "bounding-sphere radius, but the data's bounds are the single point [2, 3, 4]"));
    CHECK_THAT(e.what(), !Contains("position equals look_at"));
  }
}

TEST_CASE("tessera-render: flat data (one vertex thick) is blamed on its extent, not on the camera",
          "[robustness][messages]") {
  TempDir dir;
  dir.write("v.raw", std::string(16 * 4, '\0'));
  for (const char* dims : {"[4, 4, 1]", "[1, 4, 4]"}) {
    INFO(dims);
    dir.write("s.yaml",
              std::string("volume: {file: v.raw, dims: ") + dims +
                  ", dtype: float32}\nrenders:\n  - name: a\n"
                  "    image: {width: 4, height: 4, spp: 1}\n"
                  "    camera: {position: {orbit: {azimuth: 0, elevation: 0, distance: fit}}, look_at: center}\n"
                  "    transfer_function: {opacity: [[0, 0], [1, 1]]}\n");
    const tessera_test::CliRun r = tessera_test::run_cli(dir, "s.yaml -o out");
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Contains("the volume is one vertex thick there"));
    CHECK_THAT(r.err, Contains("likely cause: the data has no extent along "));
    CHECK_THAT(r.err, !Contains("camera too far") && !Contains("likely cause: the camera") &&
                          !Contains("likely cause: unclear"));
  }
}

TEST_CASE("adapter: a 5000-character output_dir, file name or field name is not echoed in full",
          "[robustness][messages]") {
  using namespace tessera::insitu::test;
  TempDir dir;
  const std::string renders = render_yaml("r", "", "", "density", 8, 1);
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), renders));

  SECTION("output_dir given to tessera_open_with_output_dir") {
    const std::string long_dir = dir.file(std::string(5000, 'o'));
    tessera_adapter* a = nullptr;
    const tessera_status s = tessera_open_with_output_dir(cfg.c_str(), -1, long_dir.c_str(), &a);
    const std::string e = tessera_last_error(nullptr);
    INFO(e);
    CHECK(s == TESSERA_ERROR_IO);
    CHECK(e.size() < kShortMessage);
    CHECK_THAT(e, Contains("(" + std::to_string(long_dir.size()) + " characters)"));
    if (a) tessera_close(a);
  }
  SECTION("a file name too long for the file system, at execute") {
    const std::string long_file = "    output: {file: \"{name}_" + std::string(3000, 'f') + "\", formats: [exr]}\n";
    const std::string cfg2 =
        dir.write("b.yaml", config_yaml(dir.file("out"), render_yaml("r", "", long_file, "density", 8, 1)));
    tessera_adapter* a = nullptr;
    REQUIRE(tessera_open(cfg2.c_str(), -1, &a) == TESSERA_OK);
    constexpr int n = 8;
    const std::vector<float> v = to_float(blob_values(n));
    const tessera_field f = dense_field("density", v.data(), n);
    const tessera_grid g = unit_grid(n);
    const tessera_status s = tessera_execute(a, 0, 0.0, &g, &f, 1);
    const std::string e = tessera_last_error(a);
    INFO(e);
    CHECK(s == TESSERA_ERROR_IO);
    CHECK(e.size() < kShortMessage);
    CHECK_THAT(e, Contains("fff.exr") && Contains(" characters)"));
    tessera_close(a);
  }
  SECTION("a field name passed to tessera_field_unchanged, with a BOM in it") {
    tessera_adapter* a = nullptr;
    REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
    const std::string name = kBom + std::string(5000, 'n');
    CHECK(tessera_field_unchanged(a, name.c_str()) == TESSERA_ERROR_DATA);
    const std::string e = tessera_last_error(a);
    INFO(e);
    CHECK(e.size() < kShortMessage);
    CHECK_THAT(e, Contains("called '\\u{FEFF}nnnn") && Contains("... (5003 characters)'"));
    tessera_close(a);
  }
}
