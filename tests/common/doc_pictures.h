#pragma once
// Shared by the doc-picture tests (tests/apps): a documented scene file, read with its volume
// moved to the test's own copy, and the exit status of the documented commands.
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace tessera_test {

/// The text of the YAML file at `path` with every occurrence of `documented` (the volume path
/// that its comments and its volume key name) replaced by `actual`, so that the test needs
/// nothing at the documented place; "" when the file has no volume key `file: documented`.
inline std::string doc_yaml_with_volume(const std::string& path, const std::string& documented,
                                        const std::string& actual) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  if (documented.empty() || yaml.find("file: " + documented) == std::string::npos) return "";
  for (auto at = yaml.find(documented); at != std::string::npos; at = yaml.find(documented, at + actual.size()))
    yaml.replace(at, documented.size(), actual);
  return yaml;
}

/// The exit status of shell command `cmd`, or -1 when it did not exit normally.
inline int run_command(const std::string& cmd) {
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

}  // namespace tessera_test
