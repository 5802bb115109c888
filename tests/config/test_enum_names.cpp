// The name tables (config/src/enum_names.h, core's tessera/image_format.h): every name of
// every table parses to its value, to_yaml writes that same name back, and a wrong word's
// message lists exactly the table's names.
#include <tessera/image_format.h>
#include <tessera/image_io.h>

#include "enum_names.h"
#include "test_support.h"
#include "yaml_reader.h"

#include <set>
#include <string>

using namespace tessera;
using namespace tessera::config;
using tessera::config::test::config_error;
using tessera::config::test::TempDir;
namespace cfg = tessera::config::detail;

namespace {

/// A one-render config whose `block:` holds `key: word` and `extra` (", file: x.exr").
std::string config_with(const std::string& block, const std::string& key, const std::string& word,
                        const std::string& extra = "") {
  std::string yaml = "renders:\n  - name: r\n    camera: {position: [3, 0, 0]}\n"
                     "    transfer_function: {opacity: [[0, 1]]}\n";
  if (block == "tessera") return "tessera: {" + key + ": " + word + extra + "}\n" + yaml;
  return yaml + "    " + block + ": {" + key + ": " + word + extra + "}\n";
}

/// Each row of `table`: parsed from `block.key: name` to its value (read with `get`), written
/// back by to_yaml as `key: name`, and read again to the same value. A word not in the table
/// is refused with every name of the table, in order, as the allowed values.
/// `extra(name)`: keys that value needs besides (an envmap's file, under `base_dir`).
template <class Table, class Get>
void check_round_trip(const std::string& block, const std::string& key, const Table& table, Get get,
                      std::string (*extra)(const std::string&) = nullptr, const std::string& base_dir = "") {
  std::set<std::string> seen;
  for (const auto& row : table) {
    INFO(block << "." << key << ": " << row.name);
    CHECK(seen.insert(row.name).second);  // names are unique
    const std::string more = extra ? extra(row.name) : "";
    const Config c = parse_config(config_with(block, key, row.name, more), "scene.yaml", base_dir);
    CHECK(get(c) == row.value);
    const std::string text = to_yaml(c);
    CHECK(text.find(key + ": " + row.name + "\n") != std::string::npos);
    CHECK(get(parse_config(text, "again.yaml", "")) == row.value);
  }
  const std::string message = config_error(config_with(block, key, "nonsense"));
  const std::string allowed = cfg::join_words(cfg::names_of(table));
  CHECK_THAT(message, Catch::Contains("nonsense is not allowed (allowed: " + allowed + ")"));
}

}  // namespace

TEST_CASE("every enum name round-trips through the parser and to_yaml", "[config][enum_names]") {
  check_round_trip("tessera", "on_error", cfg::kOnErrorNames, [](const Config& c) { return c.global.on_error; });
  check_round_trip("tessera", "distribution", cfg::kDistributionNames,
                   [](const Config& c) { return c.global.distribution; });
  const auto integrator = [](const Config& c) -> const IntegratorSpec& { return c.renders[0].integrator; };
  check_round_trip("integrator", "scattering", cfg::kScatteringNames,
                   [&](const Config& c) { return integrator(c).desc.scattering; });
  check_round_trip("integrator", "shading", cfg::kShadingNames,
                   [&](const Config& c) { return integrator(c).desc.shading; });
  check_round_trip("integrator", "free_path", cfg::kFreePathNames,
                   [&](const Config& c) { return integrator(c).desc.free_path; });
  check_round_trip("integrator", "majorant", cfg::kMajorantNames,
                   [&](const Config& c) { return integrator(c).desc.majorant; });
  check_round_trip("integrator", "shadow", cfg::kShadowNames,
                   [&](const Config& c) { return integrator(c).desc.shadow; });
  check_round_trip("integrator", "tile_order", cfg::kTileOrderNames,
                   [&](const Config& c) { return integrator(c).tile_order; });
  check_round_trip("output", "tonemap", cfg::kToneMapNames,
                   [](const Config& c) { return c.renders[0].output.tonemap; });
  check_round_trip("annotations", "text_corner", cfg::kCornerNames,
                   [](const Config& c) { return c.renders[0].annotations->text_corner; });
  TempDir dir;
  Image env;
  env.width = 4;
  env.height = 2;
  env.rgba.assign(4 * 2 * 4, 1.0f);
  write_exr((dir.path() / "env.exr").string(), env);
  check_round_trip(
      "background", "type", cfg::kBackgroundTypeNames, [](const Config& c) { return c.renders[0].background.type; },
      [](const std::string& type) { return std::string(type == "envmap" ? ", file: env.exr" : ""); },
      dir.path().string());
}

TEST_CASE("volume enums and light types round-trip", "[config][enum_names]") {
  TempDir dir;
  dir.write("v.raw", std::string(8 * 8, '\0'));
  for (const auto& dtype : cfg::kDTypeNames) {
    for (const auto& order : cfg::kByteOrderNames) {
      for (const auto& light : cfg::kLightTypeNames) {
        INFO(dtype.name << " " << order.name << " " << light.name);
        CHECK(std::string(dtype.name) == dtype_name(dtype.value));  // core's own name
        const std::string yaml = std::string("volume: {file: v.raw, dims: [2, 2, 2], dtype: ") + dtype.name +
                                 ", byte_order: " + order.name + "}\n" +
                                 "renders:\n  - name: r\n    camera: {position: [3, 0, 0]}\n"
                                 "    transfer_function: {opacity: [[0, 1]]}\n"
                                 "    lights: [{type: " +
                                 light.name + ", position: [0, 0, 3]}]\n";
        const Config c = parse_config(yaml, "scene.yaml", dir.path().string());
        REQUIRE(c.volume);
        CHECK(c.volume->dtype == dtype.value);
        CHECK(c.volume->byte_order == order.value);
        CHECK(c.renders[0].lights[0].index() == light.value.index());
        const Config again = parse_config(to_yaml(c), "again.yaml", "/");
        CHECK(again.volume->dtype == dtype.value);
        CHECK(again.volume->byte_order == order.value);
        CHECK(again.renders[0].lights[0].index() == light.value.index());
      }
    }
  }
  // Messages that list the allowed words take them from the tables
  CHECK_THAT(config_error("volume: {file: v.raw, dims: [2, 2, 2]}\nrenders: []\n", dir.path().string()),
             Catch::Contains("missing required key (allowed: uint8, int16, uint16, float32 or float64)"));
  const std::string render = "renders:\n  - name: r\n    camera: {position: [3, 0, 0]}\n"
                             "    transfer_function: {opacity: [[0, 1]]}\n";
  CHECK_THAT(config_error(render + "    lights: [{position: [0, 0, 1]}]\n"),
             Catch::Contains("lights[0].type: missing required key (allowed: rect or sphere)"));
  CHECK_THAT(config_error(render + "    lights: [7]\n"),
             Catch::Contains("(allowed: a mapping {type: rect | sphere, ...})"));
  CHECK_THAT(config_error(render + "    background: 7\n"),
             Catch::Contains("(allowed: a mapping {type: constant | gradient | envmap, ...})"));
}

TEST_CASE("output formats: the parser reads core's format table", "[config][output_formats]") {
  for (const ImageFormatInfo& row : image_formats()) {
    INFO(row.name);
    const Config c =
        parse_config(config_with("output", "formats", std::string("[") + row.name + "]"), "scene.yaml", "");
    REQUIRE(c.renders[0].output.formats.size() == 1);
    CHECK(c.renders[0].output.formats[0] == row.value);
    CHECK(parse_config(to_yaml(c), "again.yaml", "").renders[0].output.formats == c.renders[0].output.formats);
  }
  // A wrong word's message lists the table's names
  CHECK_THAT(config_error(config_with("output", "formats", "[tiff]")),
             Catch::Contains("tiff is not allowed (allowed: exr or png)"));
}
