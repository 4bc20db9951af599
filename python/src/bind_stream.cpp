// asynevo.Stream: live use. Event batches (numpy arrays) are pushed as they arrive and poses polled
// between batches; pipeline::EventFeed runs the frontend and the estimator in the caller's thread in the
// offline pipeline's order, so the poses equal those of run() on the same events.

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "arguments.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/pipeline/event_feed.hpp"
#include "bindings.hpp"
#include "event_arrays.hpp"
#include "results.hpp"

namespace py = pybind11;

namespace asynevo::python {

namespace {

class Stream {
 public:
  Stream(const py::object& calib, const py::object& config, const py::object& sensor,
         const std::string& backend) {
    const std::optional<pipeline::BackendKind> kind = pipeline::parseBackendKind(backend);
    if (!kind)
      throw py::value_error(
          fmt::format("backend '{}' is not window, incremental or incremental-frozen", backend));
    const auto [w, h] = sensorArg(sensor);
    const CameraModel camera = calibrationArg(calib, w, h);
    if (w > 0 && (camera.width() != w || camera.height() != h))
      throw py::value_error(fmt::format("the calibration is for {}x{} pixels but sensor is {}x{}",
                                        camera.width(), camera.height(), w, h));
    feed_ = std::make_unique<pipeline::EventFeed>(configArg(config), camera, *kind);
  }

  void push(const py::object& t, const py::object& x, const py::object& y, const py::object& p) {
    std::vector<Event> events =
        eventsFromArrays(t, x, y, p, feed_->config().sensor.width, feed_->config().sensor.height);
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    if (feed_->finished()) throw py::value_error("the stream is finished: push() after finish()");
    if (feed_->events() > 0 && !events.empty() && events.front().t_ns < feed_->lastTime())
      throw py::value_error(fmt::format("t[0] = {} is earlier than the previous batch's last event ({})",
                                        events.front().t_ns, feed_->lastTime()));
    feed_->push(events.data(), events.size());
  }

  void pushEvents(const py::dict& events) { push(events["t"], events["x"], events["y"], events["p"]); }

  py::dict poll() {
    std::vector<backend::Knot> knots;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      knots = feed_->takeFinalKnots();
      for (backend::LandmarkPoint& l : feed_->takeFinalLandmarks()) landmarks_.push_back(l);
    }
    py::dict out;
    out["trajectory"] = trajectoryArray(knots);
    out["knot_t_ns"] = knotTimes(knots);
    out["velocities"] = velocityArray(knots);
    return out;
  }

  py::object latest() {
    const auto held = lock();
    const std::optional<backend::Knot> k = feed_->newestKnot();
    if (!k) return py::none();
    return trajectoryArray(std::vector<backend::Knot>{*k})[py::int_(0)];
  }

  void finish() {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    feed_->finish();
  }

  py::dict landmarks() {
    const auto held = lock();
    for (backend::LandmarkPoint& l : feed_->takeFinalLandmarks()) landmarks_.push_back(l);
    py::dict out;
    addLandmarks(landmarks_, out);
    return out;
  }

  py::dict stats() {
    const auto held = lock();
    const backend::EstimatorStats& e = feed_->estimatorStats();
    const frontend::FrontendStats& f = feed_->frontendStats();
    py::dict s;
    s["backend"] = std::string(feed_->backendName());
    s["events"] = feed_->events();
    s["first_event_s"] = nsToSeconds(feed_->firstTime());
    s["last_event_s"] = nsToSeconds(feed_->lastTime());
    s["markers"] = feed_->markers();
    s["measurements"] = feed_->measurements();
    s["features"] = f.features_created;
    s["dropped_out_of_sensor"] = f.dropped_out_of_sensor;
    s["dropped_time_reversal"] = f.dropped_time_reversal;
    s["initialized"] = e.initialized;
    s["initialized_at_s"] = e.initialized ? nsToSeconds(e.initialized_at_ns) : 0.0;
    s["init_attempts"] = e.init_attempts;
    s["init_last_failure"] = e.init_last_failure;
    s["knots"] = e.knots;
    s["updates"] = e.updates;
    s["landmarks_created"] = e.landmarks_created;
    s["marginalizations"] = e.marginalizations;
    s["segments"] = e.segments.size();
    s["finished"] = feed_->finished();
    return s;
  }

  /// The feed's lock, waited for with the GIL released (push() in another thread holds it while it
  /// runs); the GIL is held again on return.
  std::unique_lock<std::mutex> lock() {
    std::unique_lock<std::mutex> held(mutex_, std::defer_lock);
    py::gil_scoped_release release;
    held.lock();
    return held;
  }

  int width() const { return feed_->config().sensor.width; }
  int height() const { return feed_->config().sensor.height; }

 private:
  std::unique_ptr<pipeline::EventFeed> feed_;
  std::vector<backend::LandmarkPoint> landmarks_;
  std::mutex mutex_;
};

}  // namespace

void bindStream(py::module_& m) {
  py::class_<Stream>(m, "Stream", R"doc(Live use: push event batches as they arrive, poll the poses.

The frontend and the estimator run in the calling thread during push() (the GIL is released), in the
order of the offline pipeline: the poses are those run() gives for the same events, however they are
split into batches. Knots become final (will not change any more) a window's length behind the newest
event; latest() gives the newest knot, still being refined.

Example:
  s = asynevo.Stream("calib.txt", sensor=(240, 180))
  for t, x, y, p in batches:
      s.push(t, x, y, p)
      new = s.poll()["trajectory"]      # N x 8: t [s], tx ty tz qx qy qz qw
  s.finish(); rest = s.poll()
)doc")
      .def(py::init<const py::object&, const py::object&, const py::object&, const std::string&>(),
           py::arg("calib"), py::arg("config") = py::none(), py::kw_only(), py::arg("sensor") = py::none(),
           py::arg("backend") = "window",
           R"doc(Args:
  calib: calibration file (ECD calib.txt, sized by `sensor` or 240x180, or a Kalibr camchain YAML) or a
    dict {fx, fy, cx, cy, [width, height, distortion_model, distortion]} as for run().
  config: None (defaults), a YAML file or a dict of sections, as for run().
  sensor: (width, height) or "WxH" of an ECD calib.txt (which has no size).
  backend: "window", "incremental" or "incremental-frozen".)doc")
      .def(
          "push", &Stream::push, py::arg("t"), py::arg("x"), py::arg("y"), py::arg("p"),
          R"doc(Processes a batch of events: t int64 ns (non-decreasing, not earlier than the previous batch),
x and y integer pixels inside the sensor, p bool or integer (1 ON, 0 or -1 OFF). Raises ValueError naming
the array and the index for bad input; nothing of a rejected batch is processed.)doc")
      .def("push_events", &Stream::pushEvents, py::arg("events"),
           "push(events['t'], events['x'], events['y'], events['p']) for a dict like read_events returns.")
      .def("poll", &Stream::poll,
           R"doc(The knots that became final since the last poll: dict with trajectory (N x 8: t [s], tx ty tz
qx qy qz qw), knot_t_ns (int64) and velocities (N x 7: t, vx vy vz, wx wy wz, body frame).)doc")
      .def(
          "latest", &Stream::latest,
          R"doc(The newest knot of the sliding window as [t, tx, ty, tz, qx, qy, qz, qw] (still being refined),
or None before initialization, after a tracking loss, or with a full-history backend.)doc")
      .def("finish", &Stream::finish,
           "End of the stream: final solve, every remaining knot becomes final (then poll() returns them).")
      .def("landmarks", &Stream::landmarks,
           "Landmarks handed out so far (all of them after finish()): dict with landmarks (M x 3), "
           "landmark_ids, landmark_observations.")
      .def_property_readonly("stats", &Stream::stats,
                             "Counters: events, measurements, features, initialized, knots, updates, ...")
      .def_property_readonly("width", &Stream::width, "Sensor width in pixels.")
      .def_property_readonly("height", &Stream::height, "Sensor height in pixels.");
}

}  // namespace asynevo::python
