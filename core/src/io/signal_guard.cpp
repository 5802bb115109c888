#include <tessera/signal_guard.h>

#include <pthread.h>

#include <cerrno>
#include <ctime>

namespace tessera {
namespace {
constexpr int kWriteSignals[] = {SIGXFSZ, SIGPIPE};
}  // namespace

BlockWriteSignals::BlockWriteSignals() noexcept {
  sigset_t block, pending;
  sigemptyset(&block);
  sigemptyset(&m_consume);
  sigemptyset(&pending);
  for (const int sig : kWriteSignals) sigaddset(&block, sig);
  if (pthread_sigmask(SIG_BLOCK, &block, &m_old) != 0) return;
  m_active = true;
  sigpending(&pending);
  // Ours to consume later: not blocked by the caller, not already pending
  for (const int sig : kWriteSignals)
    if (!sigismember(&m_old, sig) && !sigismember(&pending, sig)) sigaddset(&m_consume, sig);
}

BlockWriteSignals::~BlockWriteSignals() {
  if (!m_active) return;
  const int saved_errno = errno;
  sigset_t pending;
  sigemptyset(&pending);
  sigpending(&pending);
  for (const int sig : kWriteSignals) {
    if (!sigismember(&m_consume, sig) || !sigismember(&pending, sig)) continue;
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    const timespec zero{0, 0};
    while (sigtimedwait(&one, nullptr, &zero) < 0 && errno == EINTR) {
    }
  }
  pthread_sigmask(SIG_SETMASK, &m_old, nullptr);
  errno = saved_errno;
}

}  // namespace tessera
