// The C API (tessera.h): a catch-all boundary around Adapter::Impl. Nothing escapes: not an
// exception, not an abort, whatever the input or the config.
#include <tessera/tessera.h>

#include <tessera/adapter.h>

#include "adapter_impl.h"

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_set>

/// A handle. tessera_close frees the adapter (impl) but keeps this small struct and its entry
/// in the registry as a tombstone (magic word, impl == null): its address is never returned
/// by the allocator again, so a closed handle can never alias a newer one, and a second close
/// or an execute after close is recognised and refused. Cost: sizeof(tessera_adapter) (16
/// bytes) plus one hash-set node (about 32 bytes) per adapter ever opened in the process.
struct tessera_adapter {
  using Impl = tessera::insitu::Adapter::Impl;
  static constexpr std::uint64_t kMagic = 0x7e55e7a0ada97e72ull;
  std::uint64_t magic = kMagic;
  std::unique_ptr<Impl> impl;  ///< null once closed
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
tessera_status open_adapter(const char* function, const char* yaml_path, int mpi_comm_f,
                            const char* output_dir, tessera_adapter** out) noexcept {
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
    a->impl->close();
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
    case HandleState::Unknown: default: set_open_error(kUnknownMessage, function); return nullptr;
  }
}

}  // namespace

extern "C" {

tessera_status tessera_open(const char* yaml_path, int mpi_comm_f, tessera_adapter** out) {
  return open_adapter("tessera_open", yaml_path, mpi_comm_f, nullptr, out);
}

tessera_status tessera_open_with_output_dir(const char* yaml_path, int mpi_comm_f,
                                            const char* output_dir, tessera_adapter** out) {
  return open_adapter("tessera_open_with_output_dir", yaml_path, mpi_comm_f, output_dir, out);
}

tessera_status tessera_execute(tessera_adapter* adapter, int64_t step, double time,
                               const tessera_grid* grid, const tessera_field* fields,
                               int nfields) {
  tessera_status status;
  auto* impl = open_impl(adapter, "tessera_execute", &status);
  return impl ? impl->execute(step, time, grid, fields, nfields, false) : status;
}

tessera_status tessera_execute_final(tessera_adapter* adapter, int64_t step, double time,
                                     const tessera_grid* grid, const tessera_field* fields,
                                     int nfields) {
  tessera_status status;
  auto* impl = open_impl(adapter, "tessera_execute_final", &status);
  return impl ? impl->execute(step, time, grid, fields, nfields, true) : status;
}

tessera_status tessera_field_unchanged(tessera_adapter* adapter, const char* field_name) {
  tessera_status status;
  auto* impl = open_impl(adapter, "tessera_field_unchanged", &status);
  return impl ? impl->field_unchanged(field_name) : status;
}

tessera_status tessera_close(tessera_adapter* adapter) {
  if (!adapter) return TESSERA_OK;
  std::unique_ptr<tessera_adapter::Impl> impl;
  bool known = false;
  {
    std::lock_guard<std::mutex> lock(g_handles_mutex);
    known = handles().count(adapter) && adapter->magic == tessera_adapter::kMagic;
    if (known) impl = std::move(adapter->impl);  // the handle stays, as a tombstone
  }
  if (!impl) {
    set_open_error(known ? kClosedMessage : kUnknownMessage, "tessera_close");
    return TESSERA_ERROR_CONFIG;
  }
  impl->close();
  return TESSERA_OK;
}

const char* tessera_last_error(const tessera_adapter* adapter) {
  if (!adapter) return t_open_error.c_str();
  switch (state_of(adapter)) {
    case HandleState::Open: return adapter->impl->m_error.c_str();
    case HandleState::Closed: return kClosedMessage;
    case HandleState::Unknown: default: return kUnknownMessage;
  }
}

}  // extern "C"
