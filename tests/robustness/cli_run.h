#pragma once
/// Shared by the robustness tests: run tessera-render in a scratch directory with a timeout
/// (a regression fails the test instead of stalling CTest), read files back, count leftovers.
/// Test code only.
#include "temp_dir.h"

#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace tessera_test {

/// The whole file, or "" if it cannot be read.
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Files under `dir` (recursively) whose name contains `part` (e.g. ".tmp"); 0 if no `dir`.
inline int count_files(const std::string& dir, const std::string& part) {
  int n = 0;
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) return 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.path().filename().string().find(part) != std::string::npos) ++n;
  return n;
}

struct CliRun {
  int status = -1;  ///< exit status; 124 when `timeout` killed it, 128 + N for signal N
  std::string out, err;
  double seconds = 0.0;
};

#ifdef TESSERA_RENDER_EXE
/// Runs `prefix timeout T tessera-render args` inside `dir` (prefix: shell words before it,
/// e.g. "ulimit -f 2 &&"), capturing stdout, stderr and the wall time.
inline CliRun run_cli(const TempDir& dir, const std::string& args, const std::string& prefix = "", int timeout_s = 60) {
  const std::string cmd = "cd '" + dir.path().string() + "' && " + prefix + " timeout " + std::to_string(timeout_s) +
                          " '" TESSERA_RENDER_EXE "' " + args + " > cli.out 2> cli.err";
  const auto t0 = std::chrono::steady_clock::now();
  const int raw = std::system(cmd.c_str());
  CliRun r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = slurp(dir.path() / "cli.out");
  r.err = slurp(dir.path() / "cli.err");
  return r;
}
#endif

}  // namespace tessera_test
