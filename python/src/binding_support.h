#pragma once
/// What the bindings of the Python package share: the errors raised into Python and loading a
/// config from a file or from text (a dict, as JSON, from tessera/_config.py).
///
/// Every binding catches what it calls and throws a PyError, which the translator registered
/// by register_errors turns into the package's exception class (tessera/_errors.py) with its
/// attributes; no other C++ exception reaches Python except std::bad_alloc (MemoryError) and
/// argument errors (std::invalid_argument: ValueError).
#include <tessera/config/config.h>
#include <tessera/tessera.h>

#include <nanobind/nanobind.h>

#include <exception>
#include <string>

namespace tessera::python {

namespace nb = nanobind;

enum class ErrorKind { Config, Data, Render, Output, Disabled };

/// One error on its way to Python; the class is chosen by kind.
struct PyError : std::exception {
  ErrorKind kind = ErrorKind::Render;
  std::string message;
  std::string file;  ///< Config only: the file (or "config dict")
  int line = 0;      ///< Config only, 0 = unknown
  int column = 0;
  std::string key_path;  ///< Config only: renders[0].camera.fov
  const char* what() const noexcept override { return message.c_str(); }
};

/// The error for a non-OK adapter status with the adapter's message.
PyError error_for_status(tessera_status status, std::string message);

/// Loads a config: `source` is a file name (is_text false) or YAML text named `name` in
/// messages (is_text true: a dict; its messages give the key path without line and column,
/// which would point into generated text). Throws PyError of kind Config.
config::Config load_config_source(const std::string& source, bool is_text, const std::string& name);

/// Throws std::invalid_argument (ValueError) naming `what` and the position when `text` holds
/// a NUL: a C string of it would be cut there. The package checks first (tessera/_checks.py);
/// this keeps the extension from ever passing a cut name or path on.
void require_no_nul(const std::string& text, const char* what);

/// `s` as a Python str: UTF-8, any invalid byte shown as U+FFFD (a message quoting bytes of a
/// file, say) rather than a UnicodeDecodeError in place of the message.
nb::str text(const std::string& s);

/// Registers the translator, _set_error_types (called once by tessera/__init__.py) and
/// check_config (the config loaded as the adapter will load it: a ConfigError with its key
/// path, before the ranks agree and open).
void register_errors(nb::module_& m);

void register_render(nb::module_& m);
void register_adapter(nb::module_& m);
/// _dlpack_tensor (a DLPack tensor's description, never its values) and cuda_built
/// (tessera/_arrays.py: the package's one reader of the array protocols).
void register_device_arrays(nb::module_& m);

}  // namespace tessera::python
