// Robustness: loading a config within the 4 MiB cap takes bounded memory (docs/config.md
// "Limits": at most 128 MiB per rank). The worst 4 MiB files for a YAML tree (a flow list of
// one-character steps, keys without values, many small mappings) are loaded by
// `tessera-render --check` in a child; each is accepted or refused as documented, and its peak
// RSS, less that of a small config's check, stays under the bound. yaml-cpp's own tree took
// 0.9 to 1.9 GB on these. No RSS comparison under AddressSanitizer.
#include "loading_support.h"
#include "measured_child.h"

#include <catch2/catch.hpp>

#include <string>

using Catch::Matchers::Contains;
using tessera_test::TempDir;

namespace {

constexpr std::size_t kCap = std::size_t(4) << 20;
constexpr double kBoundMiB = 128.0;

/// `head`, then `unit` repeated, then `tail`, at most 4 MiB in all.
std::string fill(const std::string& head, const std::string& unit, const std::string& tail) {
  std::string s = head;
  const std::size_t n = (kCap - head.size() - tail.size()) / unit.size();
  s.reserve(kCap);
  for (std::size_t i = 0; i < n; ++i) s += unit;
  return s + tail;
}

}  // namespace

#ifdef TESSERA_RENDER_EXE
TEST_CASE("config memory: the worst 4 MiB configs load or fail within the stated memory bound",
          "[robustness][loading][memory]") {
  TempDir dir;
  const std::string head =
      tessera_test::loading::volume_block(dir) + "renders:\n" + tessera_test::loading::minimal_render();
  dir.write("small.yaml", head);
  const std::vector<std::string> env;
  const auto check = [&](const std::string& file) {
    return tessera_test::run_measured(dir, {TESSERA_RENDER_EXE, "--check", file}, env, 60);
  };
  const tessera_test::MeasuredRun base = check("small.yaml");
  REQUIRE(base.status == 0);

  const struct {
    const char* name;
    std::string text;
    const char* outcome;  // "" = accepted, else part of the error
  } cases[] = {
      {"steps.yaml", fill(head + "    trigger: {at: [", "1,", "1]}\n"), ""},
      {"bare_keys.yaml", fill(head + "    trigger: {at: 1, x: {", "a,", "a}}\n"),
       "the config has more than 2097152 YAML nodes"},
      {"small_maps.yaml", fill(head + "    trigger: {at: [", "{a: 1},", "1]}\n"),
       "renders[0].trigger.at[0]: a mapping is not allowed here"},
  };
  for (const auto& c : cases) {
    INFO(c.name);
    REQUIRE(c.text.size() <= kCap);
    dir.write(c.name, c.text);
    const tessera_test::MeasuredRun r = check(c.name);
    INFO(r.err);
    if (*c.outcome) {
      CHECK(r.status == 1);
      CHECK_THAT(r.err, Contains(std::string(c.name) + ":") && Contains(c.outcome));
    } else {
      CHECK(r.status == 0);
    }
    const double growth_mib = static_cast<double>(r.peak_rss_kib - base.peak_rss_kib) / 1024.0;
    INFO("peak RSS growth " << growth_mib << " MiB");
#if !defined(__SANITIZE_ADDRESS__)
    CHECK(growth_mib <= kBoundMiB);
#endif
  }
}
#endif
