#include "agreement/call_gate.h"

namespace tessera::insitu {

CallGate::Refusal CallGate::enter() noexcept {
  std::lock_guard<std::mutex> lock(m_mutex);
  if (m_close_running || m_closers_waiting > 0) return Refusal::Closing;
  if (m_in_call) return Refusal::Busy;
  m_in_call = true;
  return Refusal::None;
}

void CallGate::leave() noexcept {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_in_call = false;
  }
  m_idle.notify_all();
}

void CallGate::begin_close() noexcept {
  std::unique_lock<std::mutex> lock(m_mutex);
  ++m_closers_waiting;
  m_idle.wait(lock, [this] { return !m_in_call && !m_close_running; });
  --m_closers_waiting;
  m_close_running = true;
}

void CallGate::end_close() noexcept {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_close_running = false;
  }
  m_idle.notify_all();
}

std::string refusal_message(CallGate::Refusal refusal, const char* function) {
  std::string s = std::string(function) + ": refused: ";
  if (refusal == CallGate::Refusal::Closing)
    return s + "adapter is being closed by another thread (this call did nothing)";
  return s + "another thread is inside a call on this adapter (calls on one adapter must not overlap; this call "
             "did nothing)";
}

namespace {
struct Refused {
  const void* owner = nullptr;
  std::string message;
};
thread_local Refused t_refused;
}  // namespace

void note_refusal(const void* owner, const std::string& message) noexcept {
  try {
    t_refused.message = message;
    t_refused.owner = owner;
  } catch (...) {
    t_refused.owner = nullptr;
  }
}

void clear_refusal(const void* owner) noexcept {
  if (t_refused.owner == owner) t_refused.owner = nullptr;
}

const std::string* refusal_for(const void* owner) noexcept {
  return owner && t_refused.owner == owner ? &t_refused.message : nullptr;
}

}  // namespace tessera::insitu
