// libFuzzer target: tessera::config::parse_config on arbitrary bytes (scripts/fuzz.sh).
//
// Contract under test (config/include/tessera/config/config.h): parse_config returns a
// complete, validated Config or throws ConfigError; any other exception, crash or sanitizer
// report is a finding. A config that parses must also round-trip: to_yaml() of it parses again
// (it is documented to load to an equal Config), and printing that again gives the same text.
#include <tessera/config/config.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace {

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_parse_config: %s: %s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tessera::config;
  const std::string text(reinterpret_cast<const char*>(data), size);
  Config config;
  try {
    config = parse_config(text, "fuzz.yaml", "/fuzz");
  } catch (const ConfigError&) {
    return 0;  // the documented way to reject a config
  } catch (const std::exception& e) {
    finding("parse_config threw something other than ConfigError", e.what());
  }
  std::string first, second;
  try {
    first = to_yaml(config);
    second = to_yaml(parse_config(first, "fuzz-roundtrip.yaml", "/fuzz"));
  } catch (const std::exception& e) {
    finding("to_yaml output does not parse again", std::string(e.what()) + "\n--- yaml ---\n" + first);
  }
  if (first != second)
    finding("to_yaml is not a fixed point", "\n--- first ---\n" + first + "\n--- second ---\n" + second);
  return 0;
}
