// asynevo.run: the offline pipeline 'asynevo run' uses (pipeline::runDataset / runEvents), on a dataset
// or on event arrays, with the results in memory.

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "arguments.hpp"
#include "array_reader.hpp"
#include "asynevo/io/trajectory_io.hpp"
#include "asynevo/pipeline/run.hpp"
#include "asynevo/pipeline/run_folder.hpp"
#include "bindings.hpp"
#include "event_arrays.hpp"
#include "results.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace asynevo::python {

namespace {

/// The run folder: the one asked for, or a temporary folder removed when the run is over.
class RunFolder {
 public:
  explicit RunFolder(const py::handle& out) {
    if (!out.is_none()) {
      path_ = pathArg(out, "out");
      return;
    }
    std::string pattern = (fs::temp_directory_path() / "asynevo-run-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw Error("cannot create a temporary run folder in " + pattern);
    path_ = pattern;
    temporary_ = true;
  }
  ~RunFolder() {
    std::error_code ec;
    if (temporary_) fs::remove_all(path_, ec);
  }
  RunFolder(const RunFolder&) = delete;
  RunFolder& operator=(const RunFolder&) = delete;
  const std::string& path() const { return path_; }
  bool temporary() const { return temporary_; }

 private:
  std::string path_;
  bool temporary_ = false;
};

int intItem(const py::handle& mapping, const char* key) {
  const auto d = py::reinterpret_borrow<py::object>(mapping);
  return py::bool_(d.attr("__contains__")(key)) ? d[key].cast<int>() : 0;
}

/// Events given as a mapping with t, x, y, p (read_events' result, or hand-made with width and height).
pipeline::RunSummary runArrays(const py::handle& source, const py::handle& calib,
                               const py::handle& config_arg, const py::handle& sensor,
                               const pipeline::RunOptions& options, CollectingOutput& collected) {
  for (const char* key : {"t", "x", "y", "p"})
    if (!py::bool_(source.attr("__contains__")(key)))
      throw py::value_error(
          fmt::format("events have no '{}': a dict with t, x, y, p (as read_events returns)", key));
  int width = intItem(source, "width"), height = intItem(source, "height");
  if (width <= 0 || height <= 0) std::tie(width, height) = sensorArg(sensor);
  const CameraModel camera = calibrationArg(calib, width, height);
  if (width <= 0 || height <= 0) {
    width = camera.width();
    height = camera.height();
  }
  if (camera.width() != width || camera.height() != height)
    throw py::value_error(fmt::format("the calibration is for {}x{} pixels but the events are {}x{}",
                                      camera.width(), camera.height(), width, height));
  std::vector<Event> events =
      eventsFromArrays(source["t"], source["x"], source["y"], source["p"], width, height);
  Config config = configArg(config_arg);
  config.sensor.width = width;
  config.sensor.height = height;
  config.validate();
  config.validateForSensor();

  pipeline::RunSummary summary;
  summary.out_dir = options.out;
  summary.dataset_events = "<arrays>";
  summary.calibration = isPath(calib) ? pathArg(calib, "calib") : "<dict>";
  summary.format = "arrays";
  summary.width = width;
  summary.height = height;
  summary.size_origin = "the arrays";
  summary.config = config;
  py::gil_scoped_release release;
  ArrayReader reader(std::move(events), width, height, config.input.packet_size);
  pipeline::RunFolderWriter writer(options.out);
  pipeline::runEvents(reader, camera, config, options, writer, summary, {}, &collected);
  summary.peak_memory_mb = pipeline::peakMemoryMb();
  writer.writeText("stats.json", pipeline::runStatsJson(summary, options) + "\n");
  return summary;
}

py::dict run(const py::object& source, const py::object& calib, const py::object& config,
             const std::string& format, const py::object& sensor, const std::string& topic,
             const std::string& backend, const py::object& out, const std::string& rectify_map,
             const std::string& camera_info_topic) {
  const std::optional<pipeline::BackendKind> kind = pipeline::parseBackendKind(backend);
  if (!kind)
    throw py::value_error(
        fmt::format("backend '{}' is not window, incremental or incremental-frozen", backend));
  RunFolder folder(out);
  pipeline::RunOptions options;
  options.backend = *kind;
  options.out = folder.path();
  CollectingOutput collected;
  pipeline::RunSummary summary;
  if (isPath(source)) {
    options.dataset = pathArg(source, "source");
    options.format = format;
    options.topic = topic;
    options.rectify_map = rectify_map;
    options.camera_info_topic = camera_info_topic;
    const auto [w, h] = sensorArg(sensor);
    if (w > 0) options.sensor = fmt::format("{}x{}", w, h);
    if (!calib.is_none()) options.calib = pathArg(calib, "calib (with a dataset path)");
    if (isPath(config))
      options.config_path = pathArg(config, "config");
    else
      options.config = configArg(config);
    py::gil_scoped_release release;
    summary = pipeline::runDataset(options, {}, &collected);
  } else if (py::hasattr(source, "__contains__") && py::hasattr(source, "__getitem__")) {
    options.dataset = "<arrays>";
    summary = runArrays(source, calib, config, sensor, options, collected);
  } else {
    throw py::value_error("source must be a dataset path or a dict of event arrays (t, x, y, p)");
  }

  py::dict result;
  result["trajectory"] = trajectoryArray(collected.knots);
  result["knot_t_ns"] = knotTimes(collected.knots);
  result["velocities"] = velocityArray(collected.knots);
  addLandmarks(collected.landmarks, result);
  result["groundtruth"] = py::none();
  if (summary.groundtruth_poses)
    result["groundtruth"] =
        trajectoryArray(readTumTrajectory((fs::path(folder.path()) / "stamped_groundtruth.txt").string()));
  result["initialized"] = summary.initialized();
  result["message"] = summary.initialized() ? std::string() : pipeline::initializationFailureMessage(summary);
  result["stats"] = parseJson(pipeline::runStatsJson(summary, options));
  result["summary"] = pipeline::runSummaryText(summary);
  result["warnings"] = summary.warnings;
  result["out"] = folder.temporary() ? py::object(py::none()) : py::object(py::str(folder.path()));
  return result;
}

}  // namespace

void bindRun(py::module_& m) {
  m.def("run", &run, py::arg("source"), py::arg("calib") = py::none(), py::arg("config") = py::none(),
        py::kw_only(), py::arg("format") = "auto", py::arg("sensor") = py::none(), py::arg("topic") = "",
        py::arg("backend") = "window", py::arg("out") = py::none(), py::arg("rectify_map") = "",
        py::arg("camera_info_topic") = "",
        R"doc(Runs AsynEVO offline, as 'asynevo run' does, and returns the estimate in memory.

The same code as the command line: the reader (or the arrays), the frontend thread, the estimator thread
and the run folder writer, in the deterministic offline mode (same input and configuration give the
same trajectory). The GIL is released while it runs.

Args:
  source: a dataset (an ECD-style folder or an event file of any supported format; its calib.txt or
    camchain and groundtruth.txt are used), or a dict of event arrays t (int64 ns), x, y, p with optional
    width and height, e.g. what read_events returns.
  calib: calibration file (ECD calib.txt or Kalibr camchain YAML) or, for arrays, a dict
    {fx, fy, cx, cy, [width, height, distortion_model ("none", "radtan", "equidistant"), distortion]}.
    For a dataset, None uses the dataset's own calibration.
  config: None (the defaults), a YAML file, or a dict of sections, e.g. {"backend": {"knot_dt_ms": 30}}
    (keys as in docs/reference/config.md; unknown keys and bad values raise asynevo.ConfigError or
    asynevo.InputError).
  format, sensor, topic, rectify_map: as for read_events (dataset source only; arrays take their size
    from width/height, sensor or the calibration).
  camera_info_topic: a ROS bag's sensor_msgs/CameraInfo topic for the calibration, as
    --camera-info-topic (dataset source only).
  backend: "window" (AsynEVO), "incremental" or "incremental-frozen" (full-history baselines).
  out: a folder for the run folder files (stamped_traj_estimate.txt, stats.json, ...); None = a temporary
    folder, removed afterwards.

Returns:
  dict with
    trajectory: N x 8 float64, one row per knot: t [s], tx ty tz qx qy qz qw (camera-to-world)
    knot_t_ns: the knot times, int64 ns
    velocities: N x 7 float64: t [s], vx vy vz [m/s], wx wy wz [rad/s] (body frame)
    landmarks: M x 3 world points; landmark_ids (int64); landmark_observations (int32)
    groundtruth: N x 8 ground truth within the event span (dataset source with ground truth) or None
    initialized: bool; message: why initialization never succeeded ("" when it did)
    stats: the run's stats.json as a dict; summary: the command line's summary text
    warnings: list of str; out: the run folder, or None when it was temporary

Raises:
  ValueError: bad arrays (naming the array and index) or arguments.
  asynevo.InputError, asynevo.ConfigError: bad files or configuration (naming file and line).
)doc");
}

}  // namespace asynevo::python
