#pragma once
/// ErrorPolicy: what a failing render does to the adapter (`tessera: on_error`).
///   warn    - the failure is logged and returned; the next call renders as usual.
///   disable - as warn, and a render that fails `max_failures` times in a row is disabled: it
///             is not rendered again. Once every render is disabled, execute returns
///             TESSERA_ERROR_DISABLED at once.
///   abort   - the first failure stops the call; the C++ API rethrows it (AdapterError), and
///             every later execute returns the same error without rendering.
/// All ranks see the same sequence of failures (the adapter agrees on each outcome first), so
/// all ranks switch state together and none waits in a collective.
#include <tessera/config/config.h>
#include <tessera/tessera.h>

#include <cstddef>
#include <string>
#include <vector>

namespace tessera::insitu {

class ErrorPolicy {
 public:
  ErrorPolicy() = default;
  ErrorPolicy(config::OnError mode, int max_failures, std::size_t renders)
      : m_mode(mode), m_max_failures(max_failures), m_consecutive(renders, 0) {}

  config::OnError mode() const { return m_mode; }
  int max_failures() const { return m_max_failures; }

  /// True once aborted or once every render is disabled: execute must return
  /// blocked_status() without rendering.
  bool blocked() const { return m_blocked; }
  tessera_status blocked_status() const { return m_blocked_status; }
  const std::string& blocked_message() const { return m_blocked_message; }

  /// on_error: disable, and render `r` failed max_failures times in a row.
  bool disabled(std::size_t r) const {
    return m_mode == config::OnError::Disable && m_consecutive[r] >= m_max_failures;
  }

  /// Render `r` failed with `status` and `message`. Returns true if that disabled it.
  bool record_failure(std::size_t r, tessera_status status, const std::string& message);
  /// Render `r` succeeded: its consecutive-failure count restarts.
  void record_success(std::size_t r) { m_consecutive[r] = 0; }

 private:
  config::OnError m_mode = config::OnError::Warn;
  int m_max_failures = 3;
  std::vector<int> m_consecutive;  ///< per render
  std::size_t m_disabled = 0;
  bool m_blocked = false;
  tessera_status m_blocked_status = TESSERA_OK;
  std::string m_blocked_message;
};

/// One line on stderr, prefixed "tessera: ", written with a single write so that lines from
/// several ranks or threads do not interleave.
void log_line(const std::string& message) noexcept;

}  // namespace tessera::insitu
