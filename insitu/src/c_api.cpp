// The C API (tessera.h): a catch-all boundary around Adapter::Impl. Nothing escapes: not an
// exception, not an abort, whatever the input or the config.
#include <tessera/tessera.h>

#include <tessera/adapter.h>

#include "adapter_impl.h"
#include "agreement/call_gate.h"

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <unordered_set>

/// A handle. tessera_close frees the adapter (impl) but keeps this small struct and its entry
/// in the registry as a tombstone (magic word, impl == null): its address is never returned
/// by the allocator again, so a closed handle can never alias a newer one, and a second close
/// or an execute after close is recognised and refused. Cost: sizeof(tessera_adapter) (16
/// bytes) plus one hash-set node (about 32 bytes) per adapter ever opened in the process.
/// Every entry point on an open handle runs inside its gate (call_gate.h): tessera_close waits
/// for the call inside and refuses new ones meanwhile; overlapping calls are refused.
struct tessera_adapter {
  using Impl = tessera::insitu::Adapter::Impl;
  static constexpr std::uint64_t kMagic = 0x7e55e7a0ada97e72ull;
  std::uint64_t magic = kMagic;
  std::unique_ptr<Impl> impl;  ///< null once closed
  tessera::insitu::CallGate gate;
  /// What tessera_close reported, if it failed (written once, under g_handles_mutex).
  std::string close_error;
};

namespace {

/// Every handle tessera_open ever returned, open or closed (process-wide).
std::mutex g_handles_mutex;
std::unordered_set<const tessera_adapter*>& handles() {
  static auto* set = new std::unordered_set<const tessera_adapter*>;  // never destroyed: usable at exit
  return *set;
}

enum class HandleState { Open, Closed, Unknown };

HandleState state_of(const tessera_adapter* a) noexcept {
  std::lock_guard<std::mutex> lock(g_handles_mutex);
  if (!handles().count(a) || a->magic != tessera_adapter::kMagic) return HandleState::Unknown;
  return a->impl ? HandleState::Open : HandleState::Closed;
}

constexpr const char* kClosedMessage = "adapter was closed (tessera_close); open a new one with tessera_open";
constexpr const char* kUnknownMessage = "not an adapter returned by tessera_open";

/// The adapter's Impl if the handle is open; otherwise null, with the reason recorded for
/// tessera_last_error(NULL) as "function: reason" and *status set.
tessera_adapter::Impl* open_impl(tessera_adapter* a, const char* function, tessera_status* status) noexcept;

/// The calling thread's last tessera_open / tessera_open_with_output_dir failure
/// (tessera_last_error(NULL)).
thread_local std::string t_open_error;

/// Sets it to "function: message", or to message alone when function is NULL.
void set_open_error(const char* message, const char* function = nullptr) noexcept {
  try {
    t_open_error = function ? std::string(function) + ": " + message : std::string(message);
  } catch (...) {
    t_open_error.clear();
  }
}

/// tessera_open and tessera_open_with_output_dir (output_dir: nullptr or "" = the config's).
tessera_status open_adapter(const char* function, const char* yaml_path, int mpi_comm_f, const char* output_dir,
                            tessera_adapter** out) noexcept {
  if (out) *out = nullptr;
  if (!out) {
    set_open_error("out is NULL", function);
    return TESSERA_ERROR_CONFIG;
  }
  std::unique_ptr<tessera_adapter> a;
  try {
    a = std::make_unique<tessera_adapter>();
    a->impl = std::make_unique<tessera_adapter::Impl>();
  } catch (...) {
    set_open_error("out of memory", function);
    return TESSERA_ERROR_CONFIG;
  }
  const tessera_status s = a->impl->open(yaml_path, mpi_comm_f, output_dir);
  if (s != TESSERA_OK) {
    set_open_error(a->impl->m_error.c_str());
    return s;  // never handed out: freed
  }
  try {
    std::lock_guard<std::mutex> lock(g_handles_mutex);
    handles().insert(a.get());
  } catch (...) {
    a->impl->teardown();
    set_open_error("out of memory", function);
    return TESSERA_ERROR_CONFIG;
  }
  set_open_error("");
  *out = a.release();
  return TESSERA_OK;
}

tessera_adapter::Impl* open_impl(tessera_adapter* a, const char* function, tessera_status* status) noexcept {
  *status = TESSERA_ERROR_CONFIG;
  if (!a) {
    set_open_error("adapter is NULL", function);
    return nullptr;
  }
  switch (state_of(a)) {
    case HandleState::Open: *status = TESSERA_OK; return a->impl.get();
    case HandleState::Closed: set_open_error(kClosedMessage, function); return nullptr;
    case HandleState::Unknown:
    default: set_open_error(kUnknownMessage, function); return nullptr;
  }
}

/// Runs call(impl) inside the handle's gate: refused (TESSERA_ERROR_CONFIG, the message for
/// this thread's tessera_last_error(adapter)) while another call is inside or a close waits
/// or runs; the Impl cannot be freed meanwhile (tessera_close waits at the gate).
template <class Call>
tessera_status guarded(tessera_adapter* a, const char* function, Call&& call) noexcept {
  tessera_status status;
  if (!open_impl(a, function, &status)) return status;
  tessera::insitu::GateCall inside(a->gate);
  if (inside.refusal() != tessera::insitu::CallGate::Refusal::None) {
    try {
      const std::string message = tessera::insitu::refusal_message(inside.refusal(), function);
      tessera::insitu::note_refusal(a, message);
      set_open_error(message.c_str());
    } catch (...) {
    }
    return TESSERA_ERROR_CONFIG;
  }
  tessera::insitu::clear_refusal(a);
  // Closed between the check and the gate? tessera_close moves impl out only with the gate
  // shut, and the gate's mutex orders that move before this read: no registry lock needed
  if (tessera_adapter::Impl* impl = a->impl.get()) return call(*impl);
  set_open_error(kClosedMessage, function);
  return TESSERA_ERROR_CONFIG;
}

/// Per thread, per handle: the copy of the message tessera_last_error(adapter) returned last.
thread_local std::unordered_map<const tessera_adapter*, std::string> t_messages;

}  // namespace

extern "C" {

tessera_status tessera_open(const char* yaml_path, int mpi_comm_f, tessera_adapter** out) {
  return open_adapter("tessera_open", yaml_path, mpi_comm_f, nullptr, out);
}

tessera_status tessera_open_with_output_dir(const char* yaml_path, int mpi_comm_f, const char* output_dir,
                                            tessera_adapter** out) {
  return open_adapter("tessera_open_with_output_dir", yaml_path, mpi_comm_f, output_dir, out);
}

tessera_status tessera_execute(tessera_adapter* adapter, int64_t step, double time, const tessera_grid* grid,
                               const tessera_field* fields, int nfields) {
  return guarded(adapter, "tessera_execute",
                 [&](tessera_adapter::Impl& impl) { return impl.execute(step, time, grid, fields, nfields, false); });
}

tessera_status tessera_execute_final(tessera_adapter* adapter, int64_t step, double time, const tessera_grid* grid,
                                     const tessera_field* fields, int nfields) {
  return guarded(adapter, "tessera_execute_final",
                 [&](tessera_adapter::Impl& impl) { return impl.execute(step, time, grid, fields, nfields, true); });
}

tessera_status tessera_execute_domains(tessera_adapter* adapter, int64_t step, double time, const tessera_mesh* mesh,
                                       const tessera_domain* domains, int ndomains) {
  return guarded(adapter, "tessera_execute_domains", [&](tessera_adapter::Impl& impl) {
    return impl.execute_domains(step, time, mesh, domains, ndomains, false);
  });
}

tessera_status tessera_execute_domains_final(tessera_adapter* adapter, int64_t step, double time,
                                             const tessera_mesh* mesh, const tessera_domain* domains, int ndomains) {
  return guarded(adapter, "tessera_execute_domains_final", [&](tessera_adapter::Impl& impl) {
    return impl.execute_domains(step, time, mesh, domains, ndomains, true);
  });
}

tessera_status tessera_execute_mesh_domains(tessera_adapter* adapter, int64_t step, double time,
                                            const tessera_mesh_domain* domains, int ndomains) {
  return guarded(adapter, "tessera_execute_mesh_domains", [&](tessera_adapter::Impl& impl) {
    return impl.execute_mesh_domains(step, time, domains, ndomains, false);
  });
}

tessera_status tessera_execute_mesh_domains_final(tessera_adapter* adapter, int64_t step, double time,
                                                  const tessera_mesh_domain* domains, int ndomains) {
  return guarded(adapter, "tessera_execute_mesh_domains_final", [&](tessera_adapter::Impl& impl) {
    return impl.execute_mesh_domains(step, time, domains, ndomains, true);
  });
}

tessera_status tessera_execute_refused(tessera_adapter* adapter, int64_t step, double time, int domains_call,
                                       int final_step, const char* reason) {
  return guarded(adapter, "tessera_execute_refused", [&](tessera_adapter::Impl& impl) {
    return impl.execute_refused(step, time,
                                domains_call == 2   ? 2
                                : domains_call != 0 ? 1
                                                    : 0,
                                reason && *reason ? reason : "the language binding refused this rank's descriptors",
                                final_step != 0);
  });
}

tessera_status tessera_mesh_unchanged(tessera_adapter* adapter) {
  return guarded(adapter, "tessera_mesh_unchanged", [&](tessera_adapter::Impl& impl) { return impl.mesh_unchanged(); });
}

tessera_status tessera_set_cuda_stream(tessera_adapter* adapter, void* cuda_stream) {
  return guarded(adapter, "tessera_set_cuda_stream",
                 [&](tessera_adapter::Impl& impl) { return impl.set_cuda_stream(cuda_stream); });
}

tessera_status tessera_field_unchanged(tessera_adapter* adapter, const char* field_name) {
  return guarded(adapter, "tessera_field_unchanged",
                 [&](tessera_adapter::Impl& impl) { return impl.field_unchanged(field_name); });
}

tessera_status tessera_close(tessera_adapter* adapter) {
  if (!adapter) return TESSERA_OK;
  if (state_of(adapter) == HandleState::Unknown) {
    set_open_error(kUnknownMessage, "tessera_close");
    return TESSERA_ERROR_CONFIG;
  }
  // Wait for the call inside (if any) and keep new ones out; a second close waits here too
  adapter->gate.begin_close();
  std::unique_ptr<tessera_adapter::Impl> impl;
  {
    std::lock_guard<std::mutex> lock(g_handles_mutex);
    impl = std::move(adapter->impl);  // the handle stays, as a tombstone
  }
  if (!impl) {
    adapter->gate.end_close();
    set_open_error(kClosedMessage, "tessera_close");
    return TESSERA_ERROR_CONFIG;
  }
  // Collective: the ranks agree that they all close (a rank still executing is told so)
  const tessera_status s = impl->close();
  if (s != TESSERA_OK) {
    try {
      std::string message = "tessera_close: " + impl->m_error + " (the adapter is closed all the same)";
      set_open_error(message.c_str());
      std::lock_guard<std::mutex> lock(g_handles_mutex);
      adapter->close_error = std::move(message);
    } catch (...) {
    }
  }
  impl.reset();
  adapter->gate.end_close();
  return s;
}

const char* tessera_last_error(const tessera_adapter* adapter) {
  if (!adapter) return t_open_error.c_str();
  switch (state_of(adapter)) {
    case HandleState::Open: break;
    case HandleState::Closed: {
      std::lock_guard<std::mutex> lock(g_handles_mutex);
      return adapter->close_error.empty() ? kClosedMessage : adapter->close_error.c_str();
    }
    case HandleState::Unknown:
    default: return kUnknownMessage;
  }
  if (const std::string* refused = tessera::insitu::refusal_for(adapter)) return refused->c_str();
  // A copy made inside the gate: no other thread writes it, and it outlives tessera_close
  auto* a = const_cast<tessera_adapter*>(adapter);
  try {
    std::string& copy = t_messages[adapter];
    tessera::insitu::GateCall inside(a->gate);
    if (inside.refusal() != tessera::insitu::CallGate::Refusal::None) {
      copy = tessera::insitu::refusal_message(inside.refusal(), "tessera_last_error");
    } else {
      std::lock_guard<std::mutex> lock(g_handles_mutex);
      copy = a->impl ? a->impl->m_error : std::string(a->close_error.empty() ? kClosedMessage : a->close_error);
    }
    return copy.c_str();
  } catch (...) {
    return "out of memory for the message";
  }
}

}  // extern "C"
