// The render budget's keys: tessera.budget and image.min_spp, their defaults, their extremes,
// what the effective config writes, and the EXR samples channel a budget turns on.
#include "test_support.h"

using namespace tessera;
using namespace tessera::config;
using Catch::Matchers::Contains;

namespace {

std::string with(const std::string& global, const std::string& image, const std::string& output = "") {
  return (global.empty() ? std::string() : "tessera: {" + global + "}\n") +
         "renders:\n  - name: r\n    camera: {position: [3, 0, 0]}\n"
         "    transfer_function: {opacity: [[0, 1]]}\n" +
         (image.empty() ? std::string() : "    image: {" + image + "}\n") +
         (output.empty() ? std::string() : "    output: {" + output + "}\n");
}

Config parsed(const std::string& yaml) { return parse_config(yaml, "scene.yaml", ""); }

}  // namespace

TEST_CASE("tessera.budget: absent means none, a positive fraction up to 1e6 is kept exactly", "[config][budget]") {
  CHECK(parsed(with("", "")).global.budget == 0.0);
  CHECK(parsed(with("budget: 0.25", "")).global.budget == 0.25);
  CHECK(parsed(with("budget: 1e-300", "")).global.budget == 1e-300);  // tiny, but a budget
  CHECK(parsed(with("budget: 1000000", "")).global.budget == 1e6);
  CHECK(parsed(with("budget: 3", "")).global.budget == 3.0);  // rendering may take 3x the simulation
}

TEST_CASE("tessera.budget: zero, negative, NaN, infinite, too large or not a number is refused with its place",
          "[config][budget]") {
  for (const char* bad : {"0", "-0.0", "-0.1", ".nan", ".inf", "-.inf", "1000000.0001", "1e7", "lots", "[0.5]",
                          "{a: 1}", "\"0.5x\"", "true", "null"}) {
    INFO(bad);
    const std::string msg = test::config_error(with(std::string("budget: ") + bad, ""));
    CHECK_THAT(msg, Contains("scene.yaml:1:") && Contains("tessera.budget"));
  }
  // The allowed range is named
  CHECK_THAT(test::config_error(with("budget: 0", "")), Contains("(0, 1e+06]"));
}

TEST_CASE("image.min_spp: default 1, any value in [1, spp], refused outside with the key and the rule",
          "[config][budget]") {
  CHECK(parsed(with("", "")).renders[0].min_spp == 1);
  CHECK(parsed(with("", "spp: 64, min_spp: 8")).renders[0].min_spp == 8);
  CHECK(parsed(with("", "spp: 64, min_spp: 64")).renders[0].min_spp == 64);
  CHECK(parsed(with("", "min_spp: 16")).renders[0].min_spp == 16);  // the default spp is 16
  CHECK(parsed(with("", "spp: 1048576, min_spp: 1048576")).renders[0].min_spp == 1048576);

  const std::string over = test::config_error(with("", "spp: 4, min_spp: 5"));
  CHECK_THAT(over, Contains("scene.yaml:5:") && Contains("renders[0].image.min_spp") &&
                       Contains("min_spp 5 is more than image.spp 4") && Contains("1 <= min_spp <= spp"));
  CHECK_THAT(test::config_error(with("", "min_spp: 17")), Contains("more than image.spp 16"));
  for (const char* bad : {"0", "-1", "1.5", ".nan", "few", "[1]", "1048577", "99999999999999999999"}) {
    INFO(bad);
    CHECK_THAT(test::config_error(with("", std::string("spp: 64, min_spp: ") + bad)),
               Contains("scene.yaml:5:") && Contains("renders[0].image.min_spp"));
  }
}

TEST_CASE("the effective config writes the budget when there is one and min_spp always, and reads back equal",
          "[config][budget][to_yaml]") {
  const std::string none = to_yaml(parsed(with("", "")));
  CHECK(none.find("budget") == std::string::npos);  // `budget: 0` would not load again
  CHECK(none.find("min_spp: 1") != std::string::npos);

  const Config a = parsed(with("budget: 0.1", "spp: 64, min_spp: 2, denoise: true"));
  const std::string text = to_yaml(a);
  INFO(text);
  CHECK(text.find("budget: 0.1") != std::string::npos);
  CHECK(text.find("spp: 64, min_spp: 2") != std::string::npos);
  const Config b = parse_config(text, "again.yaml", "");
  CHECK(b.global.budget == 0.1);
  CHECK(b.renders[0].min_spp == 2);
  CHECK(b.renders[0].output.samples);
  CHECK(to_yaml(b) == text);
}

TEST_CASE("with a budget the EXR carries the samples channel unless the render says samples: false",
          "[config][budget]") {
  CHECK_FALSE(parsed(with("", "")).renders[0].output.samples);
  CHECK(parsed(with("budget: 0.5", "")).renders[0].output.samples);
  CHECK(parsed(with("budget: 0.5", "", "variance: true")).renders[0].output.samples);
  CHECK_FALSE(parsed(with("budget: 0.5", "", "samples: false")).renders[0].output.samples);
  CHECK(parsed(with("", "", "samples: true")).renders[0].output.samples);
  // No EXR, no channel to add
  CHECK_FALSE(parsed(with("budget: 0.5", "", "formats: [png]")).renders[0].output.samples);
}
