#pragma once
// Command line of tessera-render (docs/cli.md): what a render job takes from it (its
// overrides of the YAML); apps/tessera_render/parse_args.h reads it from argv.
#include <tessera/config/config.h>

#include <cstdint>
#include <optional>
#include <string>

namespace tessera::job {

struct Args {
  std::string scene;                                     ///< SCENE.yaml
  std::optional<std::string> render;                     ///< --render NAME
  std::optional<std::string> output;                     ///< -o OUT
  std::optional<int> spp, width, height, tile, threads;  ///< --scanline sets tile = 0
  std::optional<std::uint64_t> seed;
  /// --step N: render as the adapter does at simulation step N (frame N's random numbers,
  /// {step} = N in output names); default 0.
  std::int64_t step = 0;
  /// --time T: the simulation time of that step, for {time} in output names and annotation
  /// text (the adapter's `time` argument); finite, default 0.
  double time = 0.0;
  std::optional<std::string> stats;            ///< --stats FILE.json
  std::optional<double> time_limit;            ///< --time-limit SECONDS (overrides tessera.time_limit)
  std::optional<bool> denoise;                 ///< --denoise / --no-denoise (overrides image.denoise)
  std::optional<config::DeviceChoice> device;  ///< --device auto|cpu|cuda (overrides tessera.device)
  bool progress = false;                       ///< --progress
  bool quiet = false;                          ///< --quiet
  bool check = false;                          ///< --check: validate the scene, its renders' output paths
                                               ///< and the volume file (size), render nothing, exit 0
  bool help = false;                           ///< -h / --help: print usage, exit 0
  bool version = false;                        ///< --version
};

}  // namespace tessera::job
