#pragma once
// Python arguments turned into the library's types: paths (str or os.PathLike), a configuration (None,
// a YAML file or a dict), a calibration (a file or a dict of intrinsics) and a sensor size.

#include <pybind11/pybind11.h>

#include <string>
#include <utility>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/config/config.hpp"

namespace asynevo::python {

/// True for str and os.PathLike objects.
bool isPath(const pybind11::handle& obj);
/// os.fspath(obj) as a string; ValueError naming `what` otherwise.
std::string pathArg(const pybind11::handle& obj, const char* what);

/// None: the defaults; a path: that YAML file (loadConfig); a dict: its keys over the defaults, nested as
/// in the YAML files ({"backend": {"knot_dt_ms": 30}}), with the same checks (unknown key, wrong type,
/// out of range).
Config configArg(const pybind11::handle& config);

/// A calibration file (ECD calib.txt, whose size is width × height, or a Kalibr camchain YAML) or a dict
/// {"fx", "fy", "cx", "cy", optional "width", "height" (default: the given ones), "distortion_model"
/// ("none", "radtan", "equidistant"), "distortion" (its coefficients)}.
CameraModel calibrationArg(const pybind11::handle& calib, int width, int height);

/// (width, height) from a tuple/list of two integers or a "WxH" string; {0, 0} for None.
std::pair<int, int> sensorArg(const pybind11::handle& sensor);

}  // namespace asynevo::python
