#include <tessera/config/config_error.h>
#include <tessera/message_text.h>

#include <utility>

namespace tessera::config {
namespace {

std::string compose(const std::string& file, SourceMark mark, const std::string& key_path, const std::string& message) {
  std::string s = shown_path(file);  // a long or odd file name stays short and visible
  if (mark.line > 0) {
    s.append(":").append(std::to_string(mark.line));
    s.append(":").append(std::to_string(mark.column));
  }
  s.append(": ");
  if (!key_path.empty()) s.append(key_path).append(": ");
  s.append(message);
  return s;
}

}  // namespace

ConfigError::ConfigError(std::string file, SourceMark mark, std::string key_path, std::string message)
    : std::runtime_error(compose(file, mark, key_path, message)),
      m_file(std::move(file)),
      m_mark(mark),
      m_key_path(std::move(key_path)),
      m_message(std::move(message)) {}

}  // namespace tessera::config
