#pragma once
// The parts of the Python module 'asynevo', one function per part (module.cpp calls them in order).

#include <pybind11/pybind11.h>

namespace asynevo::python {

void bindErrors(pybind11::module_& m);    ///< asynevo.Error, InputError, ConfigError (errors.cpp)
void bindRead(pybind11::module_& m);      ///< read_events (bind_read.cpp)
void bindRun(pybind11::module_& m);       ///< run (bind_run.cpp)
void bindEvaluate(pybind11::module_& m);  ///< evaluate (bind_evaluate.cpp)
void bindStream(pybind11::module_& m);    ///< Stream (bind_stream.cpp)

}  // namespace asynevo::python
