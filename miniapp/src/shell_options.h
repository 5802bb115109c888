#pragma once
/// Command line of tessera-heat-shell (docs/miniapp.md, "A curvilinear mesh: the cylindrical
/// shell"), in tessera-heat's style:
///   tessera-heat-shell [--config FILE] [--steps N] [--grid NR NTHETA NZ] [--output-dir DIR]
#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace heat {

struct ShellOptions {
  std::string config;                            ///< "" = default_shell_config_path()
  std::int64_t steps = 100;                      ///< time steps after the initial state, >= 0
  std::array<std::int64_t, 3> grid{24, 96, 32};  ///< vertices along r, theta (columns), z; each >= 3
  std::optional<std::string> output_dir;         ///< overrides the config's tessera.output_dir
  bool help = false;
};

/// Largest vertex count per axis accepted on the command line.
inline constexpr std::int64_t kMaxShellAxis = 4096;

/// Throws std::invalid_argument with a one-line message naming the bad argument.
ShellOptions parse_shell_options(int argc, const char* const* argv);

std::string shell_usage();

/// The project's configs/heat_shell.yaml, first found of:
///   1. <dir of the executable>/../share/tessera/configs/heat_shell.yaml   (installed)
///   2. TESSERA_HEAT_SHELL_SOURCE_CONFIG, the source tree's file            (build tree)
///   3. TESSERA_HEAT_SHELL_INSTALL_CONFIG, the configured install location
/// "" if none exists.
std::string default_shell_config_path();

}  // namespace heat
