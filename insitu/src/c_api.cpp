// The C API (tessera.h): a catch-all boundary around Adapter::Impl. Nothing escapes: not an
// exception, not an abort, whatever the input or the config.
#include <tessera/tessera.h>

#include <tessera/adapter.h>

#include "adapter_impl.h"

#include <string>

struct tessera_adapter {
  tessera::insitu::Adapter::Impl impl;
};

namespace {
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
  tessera_adapter* a = nullptr;
  try {
    a = new tessera_adapter;
  } catch (...) {
    set_open_error("out of memory", function);
    return TESSERA_ERROR_CONFIG;
  }
  const tessera_status s = a->impl.open(yaml_path, mpi_comm_f, output_dir);
  if (s != TESSERA_OK) {
    set_open_error(a->impl.m_error.c_str());
    delete a;
    return s;
  }
  set_open_error("");
  *out = a;
  return TESSERA_OK;
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
  if (!adapter) return TESSERA_ERROR_CONFIG;
  return adapter->impl.execute(step, time, grid, fields, nfields, false);
}

tessera_status tessera_execute_final(tessera_adapter* adapter, int64_t step, double time,
                                     const tessera_grid* grid, const tessera_field* fields,
                                     int nfields) {
  if (!adapter) return TESSERA_ERROR_CONFIG;
  return adapter->impl.execute(step, time, grid, fields, nfields, true);
}

tessera_status tessera_field_unchanged(tessera_adapter* adapter, const char* field_name) {
  if (!adapter) {
    set_open_error("adapter is NULL", "tessera_field_unchanged");
    return TESSERA_ERROR_CONFIG;
  }
  return adapter->impl.field_unchanged(field_name);
}

tessera_status tessera_close(tessera_adapter* adapter) {
  if (!adapter) return TESSERA_OK;
  adapter->impl.close();
  delete adapter;
  return TESSERA_OK;
}

const char* tessera_last_error(const tessera_adapter* adapter) {
  if (!adapter) return t_open_error.c_str();
  return adapter->impl.m_error.c_str();
}

}  // extern "C"
