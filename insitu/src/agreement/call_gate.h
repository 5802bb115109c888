#pragma once
/// CallGate: keeps one adapter's calls and its close from racing. Each C API handle and each
/// C++ Adapter holds one. A call (execute, execute_final, field_unchanged, open,
/// tessera_last_error) enters the gate for its whole duration; close waits at the gate until
/// the call inside has returned, then runs with the gate shut.
///
///   - a call while another call is inside: refused (Busy), not serialised: two threads
///     executing one adapter is a bug in the caller, and waiting would let a second render
///     start silently after the first, on data that may have changed;
///   - a call while a close waits or runs: refused (Closing);
///   - a close while another close waits or runs: waits for it, then runs (the second finds
///     the adapter closed).
/// A call never waits, so nothing here deadlocks: close waits only for calls, and a call
/// inside an adapter cannot close it (the library calls back into nothing). The wait is
/// bounded by the call's own length (tessera.time_limit bounds a render).
///
/// A refused call cannot record its message in the adapter (the call inside owns that), so
/// the message is kept per thread: note_refusal / refusal_for (last_error shows it to the
/// refused thread only, until that thread's next call on the adapter enters).
#include <condition_variable>
#include <mutex>
#include <string>

namespace tessera::insitu {

class CallGate {
 public:
  enum class Refusal { None, Busy, Closing };

  /// Enters a call (None) or refuses it. Never blocks beyond the gate's own mutex.
  Refusal enter() noexcept;
  /// Leaves the call enter() admitted.
  void leave() noexcept;
  /// Shuts the gate and waits until no call is inside and no other close runs.
  void begin_close() noexcept;
  /// Opens the gate again (a C++ Adapter can be opened again after close).
  void end_close() noexcept;

 private:
  std::mutex m_mutex;
  std::condition_variable m_idle;
  bool m_in_call = false;
  bool m_close_running = false;
  int m_closers_waiting = 0;
};

/// A call inside the gate for the scope's lifetime (if admitted: refusal() == None).
class GateCall {
 public:
  explicit GateCall(CallGate& gate) noexcept : m_gate(gate), m_refusal(gate.enter()) {}
  ~GateCall() {
    if (m_refusal == CallGate::Refusal::None) m_gate.leave();
  }
  GateCall(const GateCall&) = delete;
  GateCall& operator=(const GateCall&) = delete;
  CallGate::Refusal refusal() const { return m_refusal; }

 private:
  CallGate& m_gate;
  CallGate::Refusal m_refusal;
};

/// "function: refused: ..." for a refused call (refusal != None).
std::string refusal_message(CallGate::Refusal refusal, const char* function);

/// Per thread: records that this thread's call on `owner` (an adapter's address) was refused
/// with `message`; clear_refusal forgets it once one of this thread's calls on owner enters.
void note_refusal(const void* owner, const std::string& message) noexcept;
void clear_refusal(const void* owner) noexcept;
/// This thread's refusal message on `owner`, or nullptr. Valid until this thread's next
/// note_refusal / clear_refusal.
const std::string* refusal_for(const void* owner) noexcept;

}  // namespace tessera::insitu
