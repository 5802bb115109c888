// number_text.h: the two ways numbers are written, as every caller (messages, YAML write-back,
// stats JSON, Cinema file names, output paths) relies on them.
#include <tessera/number_text.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using tessera::format_number;
using tessera::short_number;

TEST_CASE("format_number: shortest text that reads back as the same double", "[number_text]") {
  CHECK(format_number(30.0) == "30");
  CHECK(format_number(-12.25) == "-12.25");
  CHECK(format_number(0.1) == "0.1");
  CHECK(format_number(1e-7) == "1e-07");
  CHECK(format_number(0.1 + 0.2) == "0.30000000000000004");
  CHECK(format_number(-std::numeric_limits<double>::max()) == "-1.7976931348623157e+308");
  CHECK(format_number(std::numeric_limits<double>::infinity()) == "inf");
  CHECK(format_number(std::nan("")) == "nan");
}

TEST_CASE("short_number: six significant digits, never hundreds", "[number_text]") {
  CHECK(short_number(0.5) == "0.5");
  CHECK(short_number(1e308) == "1e+308");
  CHECK(short_number(0.1 + 0.2) == "0.3");
  CHECK(short_number(123456789.0) == "1.23457e+08");
  CHECK(short_number(-std::numeric_limits<double>::infinity()) == "-inf");
}
