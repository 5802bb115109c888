#pragma once
/// BlockWriteSignals: while alive, the calling thread does not receive SIGXFSZ (file size
/// limit: `ulimit -f`, quotas) or SIGPIPE (a pipe or socket closed by the reader), so a write
/// that hits either fails with EFBIG / EPIPE and is reported as an error instead of killing
/// the process. Every image and text writer of Tessera holds one around its write.
///
/// On destruction, an instance of either signal that this thread raised meanwhile is consumed
/// (sigtimedwait, zero timeout) before the old mask comes back: one that was already pending
/// when the guard began, or a signal the thread had blocked itself, is left alone. A
/// process-directed SIGXFSZ/SIGPIPE sent by another process while the guard is alive may be
/// consumed with it. Not copyable; use on the stack of the writing thread.
#include <signal.h>

namespace tessera {

class BlockWriteSignals {
 public:
  BlockWriteSignals() noexcept;
  ~BlockWriteSignals();
  BlockWriteSignals(const BlockWriteSignals&) = delete;
  BlockWriteSignals& operator=(const BlockWriteSignals&) = delete;

 private:
  sigset_t m_old;      ///< the thread's mask before
  sigset_t m_consume;  ///< signals this guard blocked that were not pending before
  bool m_active = false;
};

}  // namespace tessera
