#pragma once
/// The output directories of the adapters open in this process. Two adapters with the same
/// output_dir would write the same tessera_effective_config.yaml (and, with renders of the
/// same name, the same images): the second is refused at open with a message naming the
/// first's config, instead of the two overwriting each other's files. Directories compare as
/// absolute, normalised paths (symbolic links resolved as far as the path exists).
/// Thread-safe.
#include <string>

namespace tessera::insitu {

class OutputClaim {
 public:
  OutputClaim() = default;
  /// Claims `output_dir` for the adapter opened from `config_path`; throws
  /// std::invalid_argument naming the directory and the other adapter's config when another
  /// open adapter holds it.
  OutputClaim(const std::string& output_dir, const std::string& config_path);
  ~OutputClaim();
  OutputClaim(OutputClaim&& other) noexcept;
  OutputClaim& operator=(OutputClaim&& other) noexcept;
  OutputClaim(const OutputClaim&) = delete;
  OutputClaim& operator=(const OutputClaim&) = delete;

 private:
  void release() noexcept;
  std::string m_key;  ///< the claimed directory, normalised; empty: none
};

}  // namespace tessera::insitu
