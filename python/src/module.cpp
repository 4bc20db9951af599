// The Python module 'asynevo' (docs/guide/python.md).

#include "bindings.hpp"

PYBIND11_MODULE(asynevo, m) {
  m.doc() = R"doc(AsynEVO: visual odometry from pure event-camera streams.

Functions
  read_events(path, format="auto", ...)   events of any supported file or dataset folder as numpy arrays
  check_events(t, x, y, p, width, height)  the checks run() and Stream.push() make on event arrays
  run(source, calib=None, config=None, ...) the offline pipeline (as 'asynevo run') on a dataset or arrays
  evaluate(gt, est, align="sim3", ...)     ATE and relative errors (as 'asynevo eval')
  Stream(calib, config=None, ...)          feed event batches, poll poses (live use)

Conventions: time is int64 nanoseconds in event arrays and seconds (float) in trajectory arrays
(t tx ty tz qx qy qz qw, camera-to-world, w last, as TUM files). Errors: ValueError for bad arrays or
arguments (naming the array and the index), asynevo.InputError for bad files (naming file and line,
record or byte), asynevo.ConfigError for bad configuration values; both derive from asynevo.Error.
Documentation: docs/guide/python.md in the source tree.)doc";
  m.attr("__version__") = "0.1.0";
  asynevo::python::bindErrors(m);
  asynevo::python::bindRead(m);
  asynevo::python::bindRun(m);
  asynevo::python::bindEvaluate(m);
  asynevo::python::bindStream(m);
}
