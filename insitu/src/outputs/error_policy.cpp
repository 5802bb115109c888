#include "outputs/error_policy.h"

#include <unistd.h>

namespace tessera::insitu {

bool ErrorPolicy::record_failure(std::size_t r, tessera_status status, const std::string& message) {
  ++m_consecutive[r];
  switch (m_mode) {
    case config::OnError::Warn: return false;
    case config::OnError::Disable:
      if (m_consecutive[r] != m_max_failures) return false;
      if (++m_disabled == m_consecutive.size()) {
        m_blocked = true;
        m_blocked_status = TESSERA_ERROR_DISABLED;
        m_blocked_message = "rendering disabled: every render failed " + std::to_string(m_max_failures) +
                            " times in a row (on_error: disable); last: " + message;
      }
      return true;
    case config::OnError::Abort:
      m_blocked = true;
      m_blocked_status = status;
      m_blocked_message = "aborted (on_error: abort) after: " + message;
      return false;
  }
  return false;
}

void log_line(const std::string& message) noexcept {
  try {
    std::string line = "tessera: " + message;
    for (char& c : line)
      if (c == '\n') c = ' ';
    line += '\n';
    std::size_t done = 0;
    while (done < line.size()) {
      const ssize_t n = ::write(STDERR_FILENO, line.data() + done, line.size() - done);
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
  } catch (...) {
    // Out of memory while logging: drop the line.
  }
}

}  // namespace tessera::insitu
