// C++ errors as Python exceptions: asynevo::Error → asynevo.Error (a RuntimeError), with InputError and
// ConfigError as subclasses. The message is what() unchanged: file and line, record or byte offset.

#include <pybind11/pybind11.h>

#include "asynevo/core/error.hpp"
#include "bindings.hpp"

namespace py = pybind11;

namespace asynevo::python {

void bindErrors(py::module_& m) {
  // Translators registered later are tried first, so the base class goes first.
  auto& error = py::register_exception<Error>(m, "Error", PyExc_RuntimeError);
  error.attr("__doc__") =
      "Base class of AsynEVO's errors; the message names the file and line, record or byte.";
  auto& input = py::register_exception<InputError>(m, "InputError", error.ptr());
  input.attr("__doc__") =
      "Bad or unreadable input file: '<file>:<line>: <message>' (or record / byte offset).";
  auto& config = py::register_exception<ConfigError>(m, "ConfigError", error.ptr());
  config.attr("__doc__") = "A configuration value that is missing, of the wrong type or out of range.";
}

}  // namespace asynevo::python
