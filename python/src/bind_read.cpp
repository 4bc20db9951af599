// Events in and out: asynevo.read_events (any supported event file or dataset folder into numpy arrays,
// through the same readers and sensor-size rules as 'asynevo info' and 'asynevo run',
// io/dataset_reader.hpp) and asynevo.check_events (the checks run() and Stream.push() make).

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <cstdint>
#include <limits>

#include "arguments.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/dataset_reader.hpp"
#include "asynevo/io/event_reader.hpp"
#include "bindings.hpp"
#include "event_arrays.hpp"

namespace py = pybind11;

namespace asynevo::python {

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

py::dict readEvents(const py::object& path_obj, const std::string& format, const py::object& sensor,
                    const std::string& topic, const py::object& max_events_obj, const std::string& rectify_map) {
  const std::string path = pathArg(path_obj, "path");
  const auto [width, height] = sensorArg(sensor);
  uint64_t max_events = std::numeric_limits<uint64_t>::max();
  if (!max_events_obj.is_none()) {
    const auto m = max_events_obj.cast<int64_t>();
    if (m < 0) throw py::value_error(fmt::format("max_events must not be negative, not {}", m));
    max_events = static_cast<uint64_t>(m);
  }
  EventChunks chunks;
  uint64_t n = 0;
  StreamInfo info;
  ReaderStats stats;
  double parse_s = 0;
  {
    py::gil_scoped_release release;
    const DatasetFiles files = resolveDataset(path, format);
    DatasetReadSettings settings;
    settings.format = format;
    settings.topic = topic;
    settings.rectify_map = rectify_map;
    if (width > 0) settings.sensor = fmt::format("{}x{}", width, height);
    const ReaderOptions options = datasetReaderOptions(files, Config(), settings);
    const auto reader = openEventReader(files.events, options);
    auto before = Clock::now();
    while (n < max_events) {
      EventPacket packet;  // a new one each time: its events are kept, not copied
      packet.events.reserve(static_cast<std::size_t>(options.packet_size));
      const bool more = reader->read(packet);
      parse_s += seconds(Clock::now() - before);
      if (!more) break;
      if (n + packet.size() > max_events) packet.events.resize(max_events - n);
      n += packet.size();
      chunks.push_back(std::move(packet.events));
      before = Clock::now();
    }
    info = reader->info();
    stats = reader->stats();
  }
  py::dict out;
  const auto converting = Clock::now();
  addColumns(chunks, out);
  const double convert_s = seconds(Clock::now() - converting);
  out["width"] = info.width;
  out["height"] = info.height;
  out["format"] = info.format;
  out["path"] = info.path;
  out["size_origin"] = info.size_origin;
  out["rectify_map"] = info.rectify_map;
  py::dict s;
  s["events"] = n;
  s["parse_s"] = parse_s;
  s["convert_s"] = convert_s;
  s["clamped_times"] = stats.clamped_times;
  s["skipped_lines"] = stats.skipped_lines;
  s["trigger_events"] = stats.trigger_events;
  s["ignored_words"] = stats.ignored_words;
  s["imu_samples"] = stats.imu_samples;
  s["rectified_outside"] = stats.rectified_outside;
  out["stats"] = s;
  return out;
}

void checkEvents(const py::object& t, const py::object& x, const py::object& y, const py::object& p,
                 int width, int height) {
  eventsFromArrays(t, x, y, p, width, height);
}

}  // namespace

void bindRead(py::module_& m) {
  m.def("check_events", &checkEvents, py::arg("t"), py::arg("x"), py::arg("y"), py::arg("p"),
        py::arg("width"), py::arg("height"),
        R"doc(Checks event arrays as run() and Stream.push() do, without processing them.

Raises ValueError naming the array and the index: arrays of different lengths, t not integer (int64 ns)
or going backwards, x or y not integers or outside width x height, p not bool or 1 / 0 / -1, an array
that is not one-dimensional.)doc");
  m.def("read_events", &readEvents, py::arg("path"), py::arg("format") = "auto",
        py::arg("sensor") = py::none(), py::arg("topic") = "", py::arg("max_events") = py::none(),
        py::arg("rectify_map") = "",
        R"doc(Reads events from a file or a dataset folder into numpy arrays.

Any format 'asynevo run' reads: ECD text, MVSEC / DSEC-style HDF5, .aevt, Prophesee RAW (EVT 3.0 /
EVT 2.0) and DAT, AEDAT 4.0, ROS1 bags (format="auto" detects it from the content). A folder is resolved
as 'asynevo run --dataset' does (events.txt, events.aevt, ...; its sensor.yaml or camchain sets the
size). Every event is checked by the reader; bad data raises asynevo.InputError naming the file and
the line, record or byte.

Args:
  path: event file or dataset folder (str or os.PathLike).
  format: "auto", "ecd", "mvsec", "aevt", "evt3", "evt2", "dat", "aedat4", "rosbag" or "dsec".
  sensor: (width, height) or "WxH" for formats that do not state it (ECD text defaults to 240x180).
  topic: a ROS bag's event topic ("" = its only one).
  max_events: stop after this many events (None = all).
  rectify_map: DSEC: the rectification map to apply ("" = rectify_map.h5 beside the events, if any;
    "none" = raw pixels), as --rectify-map.

Returns:
  dict with
    t: int64 timestamps [ns], non-decreasing
    x, y: uint16 pixel column and row (0,0 = top-left pixel centre)
    p: int8 polarity, +1 ON, -1 OFF
    width, height: the sensor size; size_origin: where it came from
    format: the format read; path: the event file
    rectify_map: the rectification map applied ("" = none, raw pixels)
    stats: events, parse_s (time in the reader), convert_s (time filling the numpy arrays),
           clamped_times, skipped_lines, trigger_events, ignored_words, imu_samples,
           rectified_outside (events a rectification map sent outside the sensor, dropped)
)doc");
}

}  // namespace asynevo::python
