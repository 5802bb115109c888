#pragma once
/// Shared by the robustness tests: a file-size limit for the scope of a test. Test code only.
#include <signal.h>
#include <sys/resource.h>

namespace tessera_test {

/// Lowers this process's soft RLIMIT_FSIZE to `bytes` with SIGXFSZ at its default action (a
/// signal that escaped a writer kills the test, which CTest reports as a failure) and restores
/// both at scope exit.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &m_old);
    rlimit lim = m_old;
    lim.rlim_cur = bytes;
    m_ok = setrlimit(RLIMIT_FSIZE, &lim) == 0;
    m_old_action = signal(SIGXFSZ, SIG_DFL);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &m_old);
    signal(SIGXFSZ, m_old_action);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;
  bool ok() const { return m_ok; }

 private:
  rlimit m_old{};
  bool m_ok = false;
  sighandler_t m_old_action = SIG_DFL;
};

}  // namespace tessera_test
