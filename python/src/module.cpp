// tessera._tessera: the extension module of the Python package (docs/python.md).
#include "binding_support.h"

#include <nanobind/stl/string.h>

#include <stdexcept>
#include <utility>

namespace tessera::python {
namespace {

/// The package's exception classes, in ErrorKind order (set by _set_error_types). Strong
/// references kept for the life of the process: no destructor runs after Python has finalized.
PyObject* g_error_types[5] = {};

}  // namespace

PyError error_for_status(tessera_status status, std::string message) {
  PyError e;
  switch (status) {
    case TESSERA_ERROR_CONFIG: e.kind = ErrorKind::Config; break;
    case TESSERA_ERROR_DATA: e.kind = ErrorKind::Data; break;
    case TESSERA_ERROR_IO: e.kind = ErrorKind::Output; break;
    case TESSERA_ERROR_DISABLED: e.kind = ErrorKind::Disabled; break;
    default: e.kind = ErrorKind::Render; break;
  }
  e.message = std::move(message);
  return e;
}

config::Config load_config_source(const std::string& source, bool is_text, const std::string& name) {
  try {
    return is_text ? config::parse_config(source, name, "") : config::load_config(source);
  } catch (const config::ConfigError& c) {
    PyError e;
    e.kind = ErrorKind::Config;
    e.file = c.file();
    e.key_path = c.key_path();
    if (is_text && !c.key_path().empty()) {
      e.message = c.file() + ": " + c.key_path() + ": " + c.message();  // no position in a dict
    } else {
      e.message = c.what();
      e.line = c.line();
      e.column = c.column();
    }
    throw e;
  }
}

nb::str text(const std::string& s) {
  PyObject* str = PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "replace");
  if (!str) throw nb::python_error();  // out of memory
  return nb::steal<nb::str>(str);
}

void require_no_nul(const std::string& text, const char* what) {
  const std::size_t at = text.find('\0');
  if (at != std::string::npos)
    throw std::invalid_argument(std::string(what) + ": contains a NUL character at position " + std::to_string(at));
}

void register_errors(nb::module_& m) {
  m.def("_set_error_types",
        [](nb::object config, nb::object data, nb::object render, nb::object output, nb::object disabled) {
          const nb::object types[5] = {config, data, render, output, disabled};
          for (int i = 0; i < 5; ++i) {
            Py_XDECREF(g_error_types[i]);
            g_error_types[i] = types[i].inc_ref().ptr();
          }
        });
  m.def(
      "check_config",
      [](const std::string& source, bool is_text, const std::string& name) {
        if (!is_text) require_no_nul(source, "config");
        nb::gil_scoped_release unlocked;
        load_config_source(source, is_text, name);
      },
      nb::arg("source"), nb::arg("is_text"), nb::arg("name"));
  nb::register_exception_translator([](const std::exception_ptr& p, void*) {
    try {
      std::rethrow_exception(p);
    } catch (const PyError& e) {
      PyObject* type_ptr = g_error_types[static_cast<int>(e.kind)];
      if (!type_ptr) {
        PyErr_SetString(PyExc_RuntimeError, e.message.c_str());
        return;
      }
      nb::handle type(type_ptr);
      nb::object exc = e.kind == ErrorKind::Config
                           ? type(text(e.message), text(e.file), e.line, e.column, text(e.key_path))
                           : type(text(e.message));
      PyErr_SetObject(type_ptr, exc.ptr());
    }
  });
}

}  // namespace tessera::python

NB_MODULE(_tessera, m) {
  m.doc() = "Tessera's extension module; use the tessera package (docs/python.md).";
  tessera::python::register_errors(m);
  tessera::python::register_render(m);
  tessera::python::register_adapter(m);
  tessera::python::register_device_arrays(m);
}
