#pragma once
/// --output-dir: the adapter's public API has no way to override `tessera: output_dir`, so
/// tessera-heat runs on a copy of the config with that one value replaced.
///
/// The copy keeps every other line as written, so config errors still point at the user's
/// lines (only when the file has a `tessera:` block without output_dir does one line get
/// inserted). It is written as DIR/tessera_heat_config.yaml; relative file names inside the
/// config (background `file:`) are then resolved against DIR, so give those absolute.
#include <string>

namespace heat {

/// `yaml` with tessera.output_dir set to `dir` (a double-quoted YAML string).
std::string replace_output_dir(const std::string& yaml, const std::string& dir);

/// Reads `config_path`, writes the copy into `dir` (created) and returns its path. Throws
/// std::runtime_error naming the file on I/O failure.
std::string write_config_with_output_dir(const std::string& config_path, const std::string& dir);

}  // namespace heat
