// tessera-heat --output-dir (miniapp/src/config_override.cpp): the config copy differs from
// the original only in tessera.output_dir, and keeps every line number when it can.
#include "config_override.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

using heat::replace_output_dir;

namespace {
long lines(const std::string& s) { return std::count(s.begin(), s.end(), '\n'); }
}  // namespace

TEST_CASE("--output-dir replaces tessera.output_dir in place", "[heat][cli]") {
  const std::string yaml =
      "# comment\ntessera:\n  output_dir: out/heat   # where\n  on_error: warn\nrenders:\n  - name: a\n";
  const std::string out = replace_output_dir(yaml, "my dir/x");
  CHECK(out == "# comment\ntessera:\n  output_dir: \"my dir/x\"\n  on_error: warn\nrenders:\n  - name: a\n");
  CHECK(lines(out) == lines(yaml));
}

TEST_CASE("--output-dir adds output_dir where the config has none", "[heat][cli]") {
  CHECK(replace_output_dir("tessera:\n    threads: 2\nrenders: []\n", "o") ==
        "tessera:\n    output_dir: \"o\"\n    threads: 2\nrenders: []\n");
  CHECK(replace_output_dir("renders: []\n", "o") == "renders: []\ntessera: {output_dir: \"o\"}\n");
  CHECK(replace_output_dir("tessera: {threads: 2}\nrenders: []\n", "o") ==
        "tessera: {output_dir: \"o\", threads: 2}\nrenders: []\n");
  CHECK(replace_output_dir("tessera: {output_dir: a, threads: 2}\n", "q\"r") ==
        "tessera: {output_dir: \"q\\\"r\", threads: 2}\n");
}
