// The adapter's main path: open / execute / close, outputs, results, triggers that read data.
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/config/config.h>
#include <tessera/image_io.h>

#include <catch2/catch.hpp>

#include <filesystem>

namespace fs = std::filesystem;
using namespace tessera::insitu;
using namespace tessera::insitu::test;

TEST_CASE("changing the simulation's array between executes changes the image", "[insitu]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("main", "")));
  constexpr int n = 16;
  std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);  // registered once
  const tessera_grid grid = unit_grid(n);

  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  REQUIRE(adapter.execute(7, 0.7, grid, {&field, 1}) == TESSERA_OK);
  const tessera::Image first = *adapter.last_image("main");

  // The simulation moves its blob, in place
  const std::vector<float> moved = to_float(blob_values(n, 0.3));
  std::copy(moved.begin(), moved.end(), sim.begin());
  REQUIRE(adapter.execute(7, 0.7, grid, {&field, 1}) == TESSERA_OK);
  const tessera::Image second = *adapter.last_image("main");
  CHECK_FALSE(same_pixels(first, second));

  // ... and back: the same step renders the same image again (nothing cached from the data)
  const std::vector<float> back = to_float(blob_values(n));
  std::copy(back.begin(), back.end(), sim.begin());
  REQUIRE(adapter.execute(7, 0.7, grid, {&field, 1}) == TESSERA_OK);
  CHECK(same_pixels(first, *adapter.last_image("main")));
}

TEST_CASE("outputs: files per pattern and format, effective config, results", "[insitu]") {
  TempDir dir;
  const std::string out = dir.file("out/nested");
  const std::string extra = "    output: {file: \"{name}/s{step:03d}_t{time:.2f}_r{rank}\", formats: [exr, png]}\n";
  const std::string cfg = dir.write("a.yaml", config_yaml(out, render_yaml("view", "{every: 2}", extra)));
  constexpr int n = 12;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);

  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  REQUIRE(adapter.is_open());

  // The effective config: next to the outputs, and loads back to the same renders
  const std::string effective = out + "/tessera_effective_config.yaml";
  REQUIRE(fs::exists(effective));
  const tessera::config::Config reloaded = tessera::config::load_config(effective);
  REQUIRE(reloaded.renders.size() == 1);
  CHECK(reloaded.renders[0].name == "view");
  CHECK(reloaded.renders[0].output.file == "{name}/s{step:03d}_t{time:.2f}_r{rank}");

  REQUIRE(adapter.execute(1, 0.5, unit_grid(n), {&field, 1}) == TESSERA_OK);
  CHECK(adapter.last_results().empty());  // every: 2 does not fire at step 1
  REQUIRE(adapter.execute(4, 1.25, unit_grid(n), {&field, 1}) == TESSERA_OK);
  REQUIRE(adapter.last_results().size() == 1);
  const RenderResult& r = adapter.last_results()[0];
  CHECK(r.name == "view");
  CHECK(r.step == 4);
  CHECK(r.status == TESSERA_OK);
  CHECK(r.error.empty());
  REQUIRE(r.files.size() == 2);
  CHECK(r.files[0] == out + "/view/s004_t1.25_r0.exr");
  CHECK(r.files[1] == out + "/view/s004_t1.25_r0.png");
  for (const std::string& f : r.files) CHECK(fs::file_size(f) > 0);
  CHECK(r.stats.samples == 24u * 24u * 2u);
  CHECK(r.render_seconds > 0.0);
  CHECK(r.samples_per_second > 0.0);
  CHECK(r.stats.density_lookups() > 0);

  // The EXR holds the in-memory image
  const tessera::Image read = tessera::read_exr(r.files[0]);
  CHECK(same_pixels(read, *adapter.last_image("view")));
  // No temporary files left behind
  for (const auto& e : fs::recursive_directory_iterator(out))
    CHECK(e.path().filename().string().find(".tmp") == std::string::npos);

  CHECK(adapter.close() == TESSERA_OK);
  CHECK_FALSE(adapter.is_open());
  CHECK(adapter.execute(4, 1.25, unit_grid(n), {&field, 1}) == TESSERA_ERROR_CONFIG);
}

TEST_CASE("OpenOptions::output_dir moves every output and the effective config", "[insitu]") {
  // The config sits in cfg/ with a relative envmap, which must still resolve against cfg/
  TempDir dir;
  fs::create_directories(dir.file("cfg"));
  tessera::Image env;
  env.width = 8;
  env.height = 4;
  env.rgba.assign(8 * 4 * 4, 0.5f);
  tessera::write_exr(dir.file("cfg/sky.exr"), env);
  const std::string config_out = dir.file("config_out");
  const std::string override_out = dir.file("override/nested");
  const std::string extra =
      "    background: {type: envmap, file: sky.exr}\n"
      "    output: {file: \"{name}_{step:02d}\", formats: [exr, png], cinema: {azimuth: [0, 90]}}\n";
  const std::string cfg =
      dir.write("cfg/a.yaml", config_yaml(config_out, render_yaml("view", "{every: 2}", extra, "density", 12, 1)));
  constexpr int n = 8;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);

  Adapter adapter;
  adapter.set_quiet(true);
  OpenOptions options;
  options.output_dir = override_out;
  REQUIRE(adapter.open(cfg, -1, options) == TESSERA_OK);

  // The effective config is under the override and says so
  const std::string effective = override_out + "/tessera_effective_config.yaml";
  REQUIRE(fs::exists(effective));
  CHECK(tessera::config::load_config(effective).global.output_dir == override_out);

  // Images and the Cinema database go under the override; nothing under the config's dir
  REQUIRE(adapter.execute(2, 0.5, unit_grid(n), {&field, 1}) == TESSERA_OK);
  REQUIRE(adapter.last_results().size() == 1);
  const RenderResult& r = adapter.last_results()[0];
  CHECK(r.files.size() == 2 + 2 * 2);  // the main image and 2 Cinema views, EXR + PNG each
  for (const std::string& f : r.files) {
    CHECK(f.rfind(override_out + "/", 0) == 0);
    CHECK(fs::exists(f));
  }
  CHECK(fs::exists(override_out + "/view_02.exr"));
  CHECK(fs::exists(override_out + "/view_02.png"));
  CHECK(fs::exists(override_out + "/view.cdb/data.csv"));
  CHECK_FALSE(fs::exists(config_out));
  adapter.close();

  // An empty override, and the two-argument open, keep the config's output_dir
  REQUIRE(adapter.open(cfg, -1, OpenOptions{}) == TESSERA_OK);
  CHECK(fs::exists(config_out + "/tessera_effective_config.yaml"));
  REQUIRE(adapter.execute(0, 0.0, unit_grid(n), {&field, 1}) == TESSERA_OK);
  CHECK(fs::exists(config_out + "/view_00.exr"));
  CHECK_FALSE(fs::exists(override_out + "/view_00.exr"));
  fs::remove_all(config_out);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  CHECK(fs::exists(config_out + "/tessera_effective_config.yaml"));
}

TEST_CASE("OpenOptions::output_dir: errors as for the config's output_dir", "[insitu]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "")));
  OpenOptions options;
  Adapter adapter;

  // A config that fails to load fails whatever the override, and creates nothing
  options.output_dir = dir.file("override");
  const std::string bad = dir.write("bad.yaml", config_yaml(dir.file("out"), render_yaml("r", "")) + "bogus: 1\n");
  CHECK(adapter.open(bad, -1, options) == TESSERA_ERROR_CONFIG);
  CHECK_THAT(adapter.last_error(), Catch::Contains("bogus"));
  CHECK_FALSE(fs::exists(dir.file("override")));
  CHECK_FALSE(fs::exists(dir.file("out")));

  // An override that cannot be created: TESSERA_ERROR_IO naming it
  dir.write("file_in_the_way", "x");
  options.output_dir = dir.file("file_in_the_way/out");
  CHECK(adapter.open(cfg, -1, options) == TESSERA_ERROR_IO);
  CHECK_THAT(adapter.last_error(), Catch::Contains("file_in_the_way"));
  CHECK_FALSE(adapter.is_open());
  CHECK_FALSE(fs::exists(dir.file("out")));
}

TEST_CASE("OpenOptions::yaml_text: a config from memory renders as the same file does", "[insitu]") {
  TempDir dir;
  const std::string text = config_yaml(dir.file("out"), render_yaml("main", ""));
  const std::string cfg = dir.write("a.yaml", text);
  constexpr int n = 12;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);

  Adapter from_file;
  from_file.set_quiet(true);
  REQUIRE(from_file.open(cfg) == TESSERA_OK);
  REQUIRE(from_file.execute(0, 0.0, unit_grid(n), {&field, 1}) == TESSERA_OK);

  // The text, under a name that is no file: the same image (in another output_dir: two open
  // adapters may not share one)
  Adapter from_text;
  from_text.set_quiet(true);
  OpenOptions options;
  options.yaml_text = text;
  options.output_dir = dir.file("out_text");
  REQUIRE(from_text.open("config dict", -1, options) == TESSERA_OK);
  REQUIRE(from_text.execute(0, 0.0, unit_grid(n), {&field, 1}) == TESSERA_OK);
  CHECK(same_pixels(*from_file.last_image("main"), *from_text.last_image("main")));

  // Errors name the given name and the key, as for a file
  options.yaml_text = text + "bogus: 1\n";
  CHECK(from_text.open("config dict", -1, options) == TESSERA_ERROR_CONFIG);
  CHECK_THAT(from_text.last_error(), Catch::StartsWith("config dict:") && Catch::Contains("bogus"));
  CHECK_FALSE(from_text.is_open());
}

TEST_CASE("triggers: every, at, when (field maximum), render_final_step", "[insitu]") {
  TempDir dir;
  const std::string renders = render_yaml("every3", "{every: 3}") + render_yaml("at", "{at: [2, 5]}") +
                              render_yaml("hot", "{when: {above: 200}}") +
                              render_yaml("hotter", "{when: {above: 250}}");
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), renders, "  render_final_step: true\n"));
  constexpr int n = 10;
  std::vector<float> sim = to_float(blob_values(n));  // maximum 250
  const tessera_field field = dense_field("density", sim.data(), n);
  const tessera_grid grid = unit_grid(n);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);

  const auto fired = [&](std::int64_t step, bool final_step = false) {
    REQUIRE(adapter.execute(step, 0.0, grid, {&field, 1}, final_step) == TESSERA_OK);
    std::string names;
    for (const RenderResult& r : adapter.last_results()) names += r.name + " ";
    return names;
  };
  CHECK(fired(0) == "every3 hot ");
  CHECK(fired(1) == "hot ");
  CHECK(fired(2) == "at hot ");
  CHECK(fired(6) == "every3 hot ");
  sim[0] = 251.0f;  // the maximum now exceeds 250
  CHECK(fired(7) == "hot hotter ");
  sim[0] = 0.0f;
  std::fill(sim.begin(), sim.end(), 0.0f);  // nothing above 200
  CHECK(fired(8) == "");
  CHECK(fired(9) == "every3 ");
  // The final step renders everything when render_final_step is set
  CHECK(fired(11, true) == "every3 at hot hotter ");
}

TEST_CASE("execute_final without render_final_step follows the triggers", "[insitu]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "{every: 5}")));
  constexpr int n = 8;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  REQUIRE(adapter.execute(7, 0.0, unit_grid(n), {&field, 1}, true) == TESSERA_OK);
  CHECK(adapter.last_results().empty());
  REQUIRE(adapter.execute(10, 0.0, unit_grid(n), {&field, 1}, true) == TESSERA_OK);
  CHECK(adapter.last_results().size() == 1);
}

TEST_CASE("a render without `field:` uses the only published field", "[insitu]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "", "", "")));
  constexpr int n = 8;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field one = dense_field("anything", sim.data(), n);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  CHECK(adapter.execute(0, 0.0, unit_grid(n), {&one, 1}) == TESSERA_OK);
  const tessera_field two[2] = {one, dense_field("other", sim.data(), n)};
  CHECK(adapter.execute(0, 0.0, unit_grid(n), two) == TESSERA_ERROR_DATA);
  CHECK_THAT(adapter.last_error(), Catch::Contains("names no field"));
}
