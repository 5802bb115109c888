// `field: {magnitude: [a, b, c]}`: three published field names whose Euclidean norm a render
// shows; written back by to_yaml as given, a default name of its own, and every malformed form
// refused with its path and line.
#include "test_support.h"

#include <tessera/config/config.h>

using namespace tessera::config;
using Catch::Matchers::Contains;
using tessera::config::test::config_error;

TEST_CASE("field magnitude: parsed, named, keyed apart from its components and written back", "[config][magnitude]") {
  const Config c = parse_config("renders:\n  - field: {magnitude: [u, v, w]}\n  - field: u\n", "scene.yaml", "");
  REQUIRE(c.renders.size() == 2);
  const RenderSpec& r = c.renders[0];
  CHECK(r.magnitude == std::vector<std::string>{"u", "v", "w"});
  CHECK(r.field == "|u, v, w|");
  CHECK(r.name == "u_v_w_magnitude");
  CHECK(r.uses("v"));
  CHECK_FALSE(r.uses("mag"));
  CHECK(r.field_key() != c.renders[1].field_key());
  CHECK(c.renders[1].field_key() == "u");
  // Written back as given, and read again to the same render
  const std::string yaml = to_yaml(c);
  CHECK_THAT(yaml, Contains("magnitude: [u, v, w]"));
  const Config again = parse_config(yaml, "again.yaml", "");
  CHECK(again.renders[0].magnitude == r.magnitude);
  CHECK(again.renders[0].name == r.name);
  // Names that need quoting survive the round trip
  const Config q = parse_config("renders:\n  - field: {magnitude: ['a b', 'x: 1', '[c]']}\n", "q.yaml", "");
  CHECK(parse_config(to_yaml(q), "q2.yaml", "").renders[0].magnitude == q.renders[0].magnitude);
}

TEST_CASE("field magnitude: malformed forms are refused with their path", "[config][magnitude][errors]") {
  CHECK_THAT(config_error("renders:\n  - field: {magnitude: [u, v]}\n"), Contains("renders[0].field.magnitude"));
  CHECK_THAT(config_error("renders:\n  - field: {magnitude: [u, v]}\n"), Contains("three field names"));
  CHECK_THAT(config_error("renders:\n  - field: {magnitude: [u, v, w, x]}\n"), Contains("three field names"));
  CHECK_THAT(config_error("renders:\n  - field: {magnitude: u}\n"), Contains("three field names"));
  CHECK_THAT(config_error("renders:\n  - field: {norm: [u, v, w]}\n"), Contains("norm"));
  CHECK_THAT(config_error("renders:\n  - field: {}\n"), Contains("without `magnitude`"));
  CHECK_THAT(config_error("renders:\n  - field: {magnitude: [u, \"v\\x01\", w]}\n"), Contains("is not a field name"));
  CHECK_THAT(config_error("renders:\n  - field: {magnitude: [u, [v], w]}\n"),
             Contains("renders[0].field.magnitude[1]"));
}
