// Output file patterns: placeholders, specs, escapes and errors.
#include <tessera/config/output_path.h>

#include <catch2/catch.hpp>

#include <stdexcept>

using tessera::config::format_output_path;
using tessera::config::validate_output_pattern;
using Catch::Matchers::Contains;

TEST_CASE("placeholders are replaced", "[config][output_path]") {
  CHECK(format_output_path("{name}_{step:06d}", "close", 42, 0.0, 0) == "close_000042");
  CHECK(format_output_path("{name}/{step}", "a", 7, 0.0, 0) == "a/7");
  CHECK(format_output_path("r{rank:03d}_{rank}", "a", 0, 0.0, 5) == "r005_5");
  CHECK(format_output_path("{step:6d}", "a", 42, 0.0, 0) == "    42");
  CHECK(format_output_path("{step:04}", "a", -3, 0.0, 0) == "-003");
  CHECK(format_output_path("plain", "a", 1, 1.0, 1) == "plain");
}

TEST_CASE("time formats like fmt", "[config][output_path]") {
  CHECK(format_output_path("{time:.3f}", "a", 0, 1.23456, 0) == "1.235");
  CHECK(format_output_path("{time:08.2f}", "a", 0, 3.14159, 0) == "00003.14");
  CHECK(format_output_path("{time:.2e}", "a", 0, 12345.0, 0) == "1.23e+04");
  CHECK(format_output_path("{time}", "a", 0, 0.1, 0) == "0.1");  // shortest exact
  CHECK(format_output_path("{time}", "a", 0, 2.0, 0) == "2");
  CHECK(format_output_path("t{time:g}", "a", 0, 0.5, 0) == "t0.5");
}

TEST_CASE("names pad on the right, braces escape", "[config][output_path]") {
  CHECK(format_output_path("{name:6}|", "ab", 0, 0.0, 0) == "ab    |");
  CHECK(format_output_path("{{{name}}}", "x", 0, 0.0, 0) == "{x}");
}

TEST_CASE("bad patterns are errors naming the fault", "[config][output_path]") {
  CHECK_THROWS_WITH(validate_output_pattern("{name}_{frame}"), Contains("unknown placeholder {frame}"));
  CHECK_THROWS_WITH(format_output_path("{stp}", "a", 0, 0.0, 0), Contains("unknown placeholder {stp}"));
  CHECK_THROWS_WITH(validate_output_pattern("{step:.3f}"), Contains("{step:.3f} is an integer"));
  CHECK_THROWS_WITH(validate_output_pattern("{time:d}"), Contains("{time:d} is a number"));
  CHECK_THROWS_WITH(validate_output_pattern("{name:05}"), Contains("is a string"));
  CHECK_THROWS_WITH(validate_output_pattern("{step:<6}"), Contains("unsupported format spec"));
  CHECK_THROWS_WITH(validate_output_pattern("a_{name"), Contains("unclosed '{'"));
  CHECK_THROWS_WITH(validate_output_pattern("a}b"), Contains("unmatched '}'"));
  CHECK_THROWS_WITH(validate_output_pattern("{}"), Contains("unknown placeholder {}"));
  CHECK_THROWS_AS(validate_output_pattern(""), std::invalid_argument);
  CHECK_NOTHROW(validate_output_pattern("{name}_{step:06d}_{time:.3f}_r{rank:02d}"));
}
