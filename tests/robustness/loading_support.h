#pragma once
// Shared by test_loading.cpp and test_messages.cpp: parse a config to its error message, run
// tessera-render, write a small volume and a minimal scene.
#include <tessera/config/config.h>

#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_run.h"
#include "temp_dir.h"

namespace tessera_test::loading {

using tessera_test::CliRun;
using tessera_test::run_cli;

/// The message of the ConfigError that parsing `yaml` throws, or "" if it parses.
inline std::string config_error(const std::string& yaml, const std::string& base_dir = "") {
  try {
    tessera::config::parse_config(yaml, "scene.yaml", base_dir);
  } catch (const tessera::config::ConfigError& e) {
    return e.what();
  }
  return "";
}

/// The message of the ConfigError that load_config(path) throws, or "".
inline std::string load_error(const std::string& path) {
  try {
    tessera::config::load_config(path);
  } catch (const tessera::config::ConfigError& e) {
    return e.what();
  }
  return "";
}

/// Seconds since `t0`.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// A render block (as a list element of `renders:`), valid on its own.
inline std::string minimal_render(const std::string& name = "a") {
  return "  - name: " + name +
         "\n"
         "    image: {width: 4, height: 4, spp: 1}\n"
         "    camera: {position: [0.5, 0.5, 3], look_at: center}\n"
         "    transfer_function: {opacity: [[0, 0], [1, 1]]}\n";
}

/// A 2x2x2 float32 volume "v.raw" in `dir` and the `volume:` block that names it.
inline std::string volume_block(const TempDir& dir, const std::string& file = "v.raw") {
  if (file == "v.raw") dir.write("v.raw", std::string(8 * 4, '\0'));
  return "volume: {file: " + file + ", dims: [2, 2, 2], dtype: float32}\n";
}

using Run = CliRun;

}  // namespace tessera_test::loading
