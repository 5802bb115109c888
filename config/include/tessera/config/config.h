#pragma once
/// Loading a Tessera YAML config (schema and rules: docs/config.md)
/// into plain, fully validated structs. The same schema serves the in situ adapter and the
/// tessera-render CLI; the CLI additionally needs a `volume:` block.
///
/// Loading is all or nothing: load_config/parse_config return a complete Config with every
/// default filled in, or throw ConfigError naming file, line, column, key path and what is
/// allowed. Nothing here touches field data or renders.
#include <tessera/config/config_error.h>
#include <tessera/config/render_spec.h>
#include <tessera/field_view.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tessera::config {

enum class OnError { Warn, Disable, Abort };
enum class ByteOrder { Little, Big };
/// How MPI ranks share the field (docs/mpi.md): a replica per node, each rank's own block
/// with other blocks' bricks fetched on demand, or chosen by the documented rule.
enum class Distribution { Replicated, Distributed, Auto };
/// `tessera.device`: where renders trace (device_choice.h resolves it per render).
enum class DeviceChoice { Auto, Cpu, Cuda };

/// `tessera:` global options.
struct GlobalOptions {
  /// Directory every relative output path is written under; kept as written (a relative
  /// directory is relative to the process's working directory, not to the YAML file).
  std::string output_dir = "out";
  OnError on_error = OnError::Warn;
  int threads = 0;                 ///< >= 0; 0 = all hardware threads
  bool render_final_step = false;  ///< adapter: tessera_execute_final renders everything
  int max_failures = 3;            ///< adapter, on_error: disable: failures before disabling, >= 1
  /// Seconds one render may take (every Cinema view included), in [0, kMaxTimeLimit];
  /// 0 = no limit. Past it every rank stops at its next tile and the render fails.
  double time_limit = 0.0;
  /// Megabytes one render's own allocations may take on one rank (film, images, replica,
  /// envmap), in [0, kMaxMemoryLimitMb]; 0 = the documented default derived from the
  /// machine's memory (docs/insitu.md, "Limits and failure").
  std::int64_t memory_limit_mb = 0;
  /// Adapter under MPI: replicated | distributed | auto (docs/mpi.md, "Distributed mode").
  Distribution distribution = Distribution::Auto;
  /// Distributed mode: the most the cache of other ranks' bricks may hold, as a fraction of
  /// the global field's bytes, in (0, 1] (and always within memory_limit_mb). The default
  /// keeps a rank under half of what a replica costs; 1 lets the cache hold every brick.
  double brick_cache = kDefaultBrickCache;
  /// Adapter: the render budget, the most of the simulation's wall time that rendering may
  /// take over the run (0.25 = a quarter), in (0, kMaxBudget]; 0 = no budget (the key left
  /// out; `budget: 0` is refused). With a budget each render's samples per pixel are planned
  /// between its `image.min_spp` and `image.spp` (docs/insitu.md, "Controlling the cost").
  double budget = 0.0;
  /// auto: on the GPU when the field's arrays are device (or managed) memory and Tessera has
  /// CUDA, else on the CPU; cpu: host threads; cuda: the GPU whatever the data (docs/gpu.md).
  DeviceChoice device = DeviceChoice::Auto;
  /// -1: the node-local MPI rank modulo the visible devices; else a device index, in
  /// [-1, kMaxCudaDevice] (checked against the devices visible when a render resolves it).
  int cuda_device = -1;

  static constexpr int kMaxCudaDevice = 4095;
  static constexpr double kMaxBudget = 1e6;
  static constexpr double kMaxTimeLimit = 31536000.0;  ///< one year, in seconds
  static constexpr std::int64_t kMaxMemoryLimitMb = std::int64_t(1) << 40;
  static constexpr double kDefaultBrickCache = 0.4;
};

/// `volume:` (CLI only): a raw binary array of dims[0]*dims[1]*dims[2] values, i fastest.
struct VolumeSpec {
  std::string file;                  ///< resolved against the YAML file's directory
  std::int64_t dims[3] = {1, 1, 1};  ///< each >= 1
  DType dtype = DType::Float32;
  Vec3 spacing{1.0};  ///< each > 0
  Vec3 origin{0.0};
  ByteOrder byte_order = ByteOrder::Little;
  std::int64_t header_bytes = 0;  ///< >= 0, skipped at the start of the file
  /// What a value is: a vertex's, or a cell's (at its centre; the medium fills the cells' box)
  Association association = Association::Vertex;

  VolumeGeometry geometry() const { return VolumeGeometry{origin, spacing, association}; }
};

struct Config {
  std::string path;  ///< the file it was loaded from (as given; for messages)
  GlobalOptions global;
  std::optional<VolumeSpec> volume;
  std::vector<RenderSpec> renders;  ///< at least one, names unique

  /// The render called `name`, or nullptr.
  const RenderSpec* find_render(const std::string& name) const;
};

/// Reads and validates `path`. Relative file names inside (volume.file, background.file) are
/// resolved against the directory of `path`.
Config load_config(const std::string& path);

/// Validates YAML text. `file_name_for_messages` is what error messages print as FILE;
/// `base_dir` is what relative file names inside are resolved against ("" = as written).
Config parse_config(const std::string& yaml_text, const std::string& file_name_for_messages,
                    const std::string& base_dir);

/// The effective config, every default written out, as YAML that parse_config accepts again
/// and that loads to an equal Config. File names are written absolute.
std::string to_yaml(const Config& config);

/// Lower-case names as written in configs.
const char* on_error_name(OnError e);

}  // namespace tessera::config
