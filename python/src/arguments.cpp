#include "arguments.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <vector>

#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/sensor_size.hpp"

namespace py = pybind11;

namespace asynevo::python {

bool isPath(const py::handle& obj) { return py::isinstance<py::str>(obj) || py::hasattr(obj, "__fspath__"); }

std::string pathArg(const py::handle& obj, const char* what) {
  if (!isPath(obj))
    throw py::value_error(fmt::format("{} must be a path (str or os.PathLike), not {}", what,
                                      py::str(py::type::of(obj).attr("__name__")).cast<std::string>()));
  return py::str(py::module_::import("os").attr("fspath")(obj)).cast<std::string>();
}

Config configArg(const py::handle& config) {
  if (config.is_none()) return Config();
  if (isPath(config)) return loadConfig(pathArg(config, "config"));
  if (!py::isinstance<py::dict>(config))
    throw py::value_error("config must be None, a YAML file path or a dict of sections ({'backend': {...}})");
  // JSON is YAML (flow style): the dict goes through the same loader as a file, with the same checks.
  const std::string text = py::str(py::module_::import("json").attr("dumps")(config)).cast<std::string>();
  Config result;
  applyConfigYaml(text, "the config dict", result);
  return result;
}

namespace {

double number(const py::dict& d, const char* key) {
  if (!d.contains(key))
    throw py::value_error(fmt::format("calib dict has no '{}' (it needs fx, fy, cx, cy)", key));
  return py::float_(d[key]).cast<double>();
}

DistortionModel distortionModel(const std::string& name) {
  if (name == "none") return DistortionModel::kNone;
  if (name == "radtan") return DistortionModel::kRadtan;
  if (name == "equidistant") return DistortionModel::kEquidistant;
  throw py::value_error(fmt::format("calib distortion_model '{}' is not none, radtan or equidistant", name));
}

}  // namespace

CameraModel calibrationArg(const py::handle& calib, int width, int height) {
  if (calib.is_none())
    throw py::value_error("a calibration is needed: calib=FILE or a dict {fx, fy, cx, cy}");
  if (isPath(calib))
    return readCalibration(pathArg(calib, "calib"), width > 0 ? width : 240, height > 0 ? height : 180);
  if (!py::isinstance<py::dict>(calib))
    throw py::value_error("calib must be a file path or a dict {fx, fy, cx, cy}");
  const auto d = py::reinterpret_borrow<py::dict>(calib);
  const int w = d.contains("width") ? d["width"].cast<int>() : width;
  const int h = d.contains("height") ? d["height"].cast<int>() : height;
  if (w <= 0 || h <= 0)
    throw py::value_error("calib dict: the sensor size is unknown; give its width and height");
  const DistortionModel model =
      distortionModel(d.contains("distortion_model") ? d["distortion_model"].cast<std::string>() : "none");
  const std::vector<double> coefficients =
      d.contains("distortion") ? d["distortion"].cast<std::vector<double>>() : std::vector<double>{};
  try {
    return CameraModel(w, h, number(d, "fx"), number(d, "fy"), number(d, "cx"), number(d, "cy"), model,
                       coefficients);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("calib dict: ") + e.what());
  }
}

std::pair<int, int> sensorArg(const py::handle& sensor) {
  if (sensor.is_none()) return {0, 0};
  if (py::isinstance<py::str>(sensor)) {
    const SensorSize size = parseSensorSize(sensor.cast<std::string>(), "sensor");
    return {size.width, size.height};
  }
  try {
    const auto wh = sensor.cast<std::pair<int, int>>();
    if (wh.first > 0 && wh.second > 0) return wh;
  } catch (const py::cast_error&) {
  }
  throw py::value_error("sensor must be (width, height) or 'WxH' with positive sizes");
}

}  // namespace asynevo::python
