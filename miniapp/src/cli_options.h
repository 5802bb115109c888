#pragma once
/// Command line of tessera-heat (docs/miniapp.md):
///   tessera-heat [--config FILE] [--steps N] [--grid NX NY NZ] [--output-dir DIR] [--dump FILE]
///                [--work-ms N] [--domains-per-rank N] [--cell] [--amr [--levels 2|3] [--ratio 2|4]]
///                [--device cpu|cuda]
#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace heat {

/// Where the simulation runs and its field lives (--device).
enum class Device {
  cpu,  ///< HeatSolver: host memory
  cuda  ///< CudaHeatSolver: one GPU per rank, the field in device memory (docs/miniapp_gpu.md)
};

struct Options {
  std::string config;                            ///< "" = default_config_path()
  std::int64_t steps = 100;                      ///< time steps after the initial state, >= 0
  std::array<std::int64_t, 3> grid{64, 64, 64};  ///< global vertices, each >= 3
  std::optional<std::string> output_dir;         ///< overrides the config's tessera.output_dir
  std::optional<std::string> dump;               ///< raw float32 file of the final global field
  std::int64_t work_ms = 0;                      ///< computation added to each step, [0, kMaxWorkMs]
  /// --domains-per-rank N: publish each rank's array as N uneven domains
  /// (tessera_execute_domains); 0 = one block per rank through tessera_execute
  std::int64_t domains_per_rank = 0;
  bool cell = false;  ///< publish the values as cells centred on the vertices (through domains)
  /// --amr: refined levels following a heat source (amr_levels.h), through domains
  bool amr = false;
  int levels = 2;  ///< --levels: 2 or 3 (with --amr)
  int ratio = 2;   ///< --ratio: 2 or 4 (with --amr)
  /// --device: cuda publishes one block per rank, so it refuses --amr, --cell and
  /// --domains-per-rank
  Device device = Device::cpu;
  bool help = false;
};

/// Throws std::invalid_argument with a one-line message naming the bad argument. (Whether
/// --device cuda can run, a CUDA build and a visible device, is checked by the run.)
Options parse_options(int argc, const char* const* argv);

std::string usage();

/// The project's configs/heat.yaml, first found of:
///   1. <dir of the executable>/../share/tessera/configs/heat.yaml   (an installed tessera-heat)
///   2. TESSERA_HEAT_SOURCE_CONFIG, the source tree's file            (a build-tree tessera-heat)
///   3. TESSERA_HEAT_INSTALL_CONFIG, the configured install location
/// (2 and 3 are fixed when the miniapp is compiled). "" if none exists.
std::string default_config_path();

}  // namespace heat
