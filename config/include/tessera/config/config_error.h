#pragma once
/// ConfigError: the one exception type the config module throws for a bad config file.
#include <stdexcept>
#include <string>

namespace tessera::config {

/// A position in a config file, 1-based. line == 0 means "no position" (e.g. the file could
/// not be opened).
struct SourceMark {
  int line = 0;
  int column = 0;
};

/// A config that failed to load. what() reads
///   `FILE:LINE:COL: KEY.PATH: what is wrong (what is allowed)`
/// e.g. `scene.yaml:12:7: renders[0].camera.fov: 270 is out of range (0, 180)`.
/// Parts that are unknown are left out: no position gives `FILE: KEY.PATH: ...`, no key path
/// (a YAML syntax error, an unreadable file) gives `FILE:LINE:COL: ...`. FILE is shown as
/// tessera::shown_path gives it (escaped, a long one cut in the middle); file() is the whole.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string file, SourceMark mark, std::string key_path, std::string message);

  const std::string& file() const { return m_file; }
  int line() const { return m_mark.line; }
  int column() const { return m_mark.column; }
  const std::string& key_path() const { return m_key_path; }
  /// The message alone, without file, position and key path.
  const std::string& message() const { return m_message; }

 private:
  std::string m_file;
  SourceMark m_mark;
  std::string m_key_path;
  std::string m_message;
};

}  // namespace tessera::config
