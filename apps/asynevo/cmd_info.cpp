// 'asynevo info --dataset PATH': what a dataset holds, from one streaming pass over its events.
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/dataset_reader.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/event_statistics.hpp"
#include "asynevo/io/groundtruth_reader.hpp"
#include "asynevo/io/rosbag_topics.hpp"
#include "commands.hpp"
#include "progress.hpp"
#include "sensor_option.hpp"

namespace asynevo::cli {

namespace {

struct InfoOptions {
  std::string dataset;
  std::string format = "auto";
  std::string config;
  std::string sensor;
  std::string topic;
  std::string gt_topic;
  std::string camera_info_topic;
  std::string rectify_map;
};

// The event topic a ROS bag's reader delivers ("" for other formats).
std::string bagEventTopic(const EventReader& reader) {
  for (const ContainerStream& t : reader.stats().streams) {
    if (t.delivered && reader.info().format == "rosbag") return t.name;
  }
  return "";
}

// The streams of a container file (AEDAT 4.0), one line each: id, type, name, size, packets, elements.
void printContainerStreams(const std::vector<ContainerStream>& streams) {
  const char* label = "streams       ";
  for (const ContainerStream& s : streams) {
    std::string line = fmt::format("{}id {} {}", label, s.id, s.type.empty() ? "(no type)" : s.type);
    if (!s.name.empty()) line += " '" + s.name + "'";
    if (s.width > 0) line += fmt::format(" {}x{}", s.width, s.height);
    line += fmt::format(": {} packets", s.packets);
    if (s.delivered) {
      line += fmt::format(", {} events (read)", s.elements);
    } else if (s.type == "IMUS" || s.type == "TRIG") {
      line += fmt::format(", {} {} (counted)", s.elements, s.type == "IMUS" ? "samples" : "triggers");
    } else {
      line += s.type == "EVTS" ? " (skipped: only the first event stream is read)" : " (skipped)";
    }
    fmt::print("{}\n", line);
    label = "              ";
  }
}

// The topics of a ROS bag, one line each: topic, message type, messages; the event topic read is marked.
void printBagTopics(const std::vector<ContainerStream>& topics) {
  const char* label = "topics        ";
  for (const ContainerStream& t : topics) {
    std::string line = fmt::format("{}{}  {}  {} messages", label, t.name, t.type, t.packets);
    if (t.delivered) line += fmt::format(" (events read from here: {} events)", t.elements);
    fmt::print("{}\n", line);
    label = "              ";
  }
  for (const ContainerStream& t : topics) {
    if (t.delivered) fmt::print("event topic   {}\n", t.name);
  }
}

void runInfo(const InfoOptions& options) {
  const Config config = options.config.empty() ? Config() : loadConfig(options.config);
  const DatasetFiles files = resolveDataset(options.dataset, options.format);
  checkGroundTruthChoice(files, options.gt_topic);
  std::vector<std::string> notes;
  const ReaderOptions reader_options = datasetReaderOptions(
      files, config, {options.format, options.sensor, "", options.config, options.topic, options.rectify_map},
      &notes);
  auto reader = openEventReader(files.events, reader_options);
  Progress progress;
  int64_t first_t_ns = 0;
  const EventStatistics stats = computeEventStatistics(*reader, 10'000'000, [&](uint64_t n, int64_t t_ns) {
    if (first_t_ns == 0 && n > 0) first_t_ns = t_ns;
    progress.update(n, t_ns, first_t_ns);
  });
  progress.finish();
  if (stats.events == 0) throw InputError(files.events, "the file holds no events");

  const auto& info = reader->info();
  char first[32], last[32];
  formatNsAsSeconds(stats.first_t_ns, first);
  formatNsAsSeconds(stats.last_t_ns, last);
  fmt::print("dataset       {}\n", files.root);
  fmt::print("events file   {}\n", info.path);
  fmt::print("format        {}\n", info.format);
  fmt::print("sensor        {} x {} (from {})\n", info.width, info.height, info.size_origin);
  for (const std::string& note : notes) fmt::print("              note: {}\n", note);
  const bool rectified = !info.rectify_map.empty();
  if (rectified) {
    fmt::print(
        "rectification {}: events in the rectified camera's pixels (rounded), {} mapped outside the "
        "sensor (dropped)\n",
        info.rectify_map, reader->stats().rectified_outside);
  } else if (info.format == "dsec") {
    fmt::print("rectification none: events in raw pixels (no {} beside the events, or --rectify-map none)\n",
               "rectify_map.h5");
  }
  fmt::print("events        {}\n", stats.events);
  fmt::print("time span     {} .. {} s ({:.6f} s)\n", first, last, stats.durationSeconds());
  fmt::print("event rate    mean {:.3f} M events/s; over {} ms windows: median {:.3f}, max {:.3f} M events/s (at {:.3f} s)\n",
             stats.mean_rate * 1e-6, stats.window_ns / 1'000'000, stats.median_window_rate * 1e-6,
             stats.max_window_rate * 1e-6, nsToSeconds(stats.max_window_start_ns));
  fmt::print("polarity      {:.1f} % ON, {:.1f} % OFF\n", 100.0 * stats.onFraction(), 100.0 * (1.0 - stats.onFraction()));
  fmt::print("pixels        {} of {} fired ({:.1f} %), busiest pixel {} events\n", stats.active_pixels,
             info.width * info.height, 100.0 * static_cast<double>(stats.active_pixels) / (info.width * info.height),
             stats.max_pixel_events);
  if (stats.clamped_times > 0) fmt::print("clamped       {} events whose time went slightly backwards\n", stats.clamped_times);
  if (reader->stats().trigger_events > 0)
    fmt::print("triggers      {} external-trigger events (counted, not used)\n", reader->stats().trigger_events);
  if (reader->stats().imu_samples > 0)
    fmt::print("imu           {} samples (counted, not used)\n", reader->stats().imu_samples);
  if (info.format == "rosbag") {
    printBagTopics(reader->stats().streams);
    // EventPacket events carry the camera's clock; the first packet's header stamp is ROS time
    // (docs/reference/formats_rosbag.md#clocks).
    for (const ContainerStream& t : reader->stats().streams) {
      if (!t.delivered) continue;
      if (const std::optional<int64_t> stamp = rosbagFirstPacketStamp(files.events, t.name)) {
        char ros[32];
        formatNsAsSeconds(*stamp, ros);
        fmt::print("clocks        events in the camera's clock (first event {} s); the first packet's header stamp "
                   "(ROS time) is {} s: ROS time - camera time = {:.6f} s, up to the driver's latency\n",
                   first, ros, nsToSeconds(*stamp - stats.first_t_ns));
      }
    }
  } else {
    printContainerStreams(reader->stats().streams);
  }
  if (reader->stats().ignored_words > 0) {
    fmt::print("skipped       {} encoded words (vendor extension words, events before the first time base)\n",
               reader->stats().ignored_words);
  }
  // Calibration: --camera-info-topic, a file beside the events (calib.txt, a camchain), a bag's CameraInfo
  // topic (chooseDatasetCalibration).
  const bool bag = info.format == "rosbag";
  const DatasetCalibration calibration =
      chooseDatasetCalibration(files, "", options.camera_info_topic, bagEventTopic(*reader));
  if (!calibration.file.empty()) {
    const CameraModel camera = readCalibration(calibration.file, info.width, info.height);
    fmt::print("calibration   {}\n              {}\n", calibration.file, camera.summary());
    if (camera.width() != info.width || camera.height() != info.height)
      fmt::print("              warning: calibration is {}x{} but the events are {}x{}\n", camera.width(),
                 camera.height(), info.width, info.height);
    if (!calibration.note.empty()) fmt::print("              note: {}\n", calibration.note);
  } else if (const std::optional<BagCalibration>& calib = calibration.bag) {
    fmt::print("calibration   {}\n              {}\n", bagTopicSource(files.events, calib->topic),
               calib->camera.summary());
    if (calib->camera.width() != info.width || calib->camera.height() != info.height)
      fmt::print("              warning: the camera info is for {}x{} pixels but the events are {}x{} (a run stops "
                 "with an error)\n",
                 calib->camera.width(), calib->camera.height(), info.width, info.height);
    if (!calibration.note.empty()) fmt::print("              note: {}\n", calibration.note);
  } else {
    fmt::print("calibration   none found (a run needs --calib)\n");
  }
  if (rectified) {
    fmt::print(
        "              note: the events are rectified: the calibration that applies is DSEC's "
        "rectified camera (cam_to_cam.yaml intrinsics camRect0 or camRect3: camera_matrix, no "
        "distortion), not the raw one\n");
  }
  const std::optional<DatasetGroundTruth> gt = loadDatasetGroundTruth(files, options.gt_topic);
  if (gt) {
    char gt_first[32], gt_last[32];
    formatNsAsSeconds(gt->poses.front().t_ns, gt_first);
    formatNsAsSeconds(gt->poses.back().t_ns, gt_last);
    const auto inside = std::count_if(gt->poses.begin(), gt->poses.end(), [&](const StampedPose& p) {
      return p.t_ns >= stats.first_t_ns && p.t_ns <= stats.last_t_ns;
    });
    fmt::print("ground truth  {}\n              {} poses, {} .. {} s, {} inside the event span\n", gt->source,
               gt->poses.size(), gt_first, gt_last, inside);
    if (!gt->note.empty()) fmt::print("              note: {}\n", gt->note);
    if (inside == 0) {
      fmt::print("              warning: the ground truth and the events do not overlap in time{}\n",
                 bag ? " (EventPacket events carry the camera's clock, poses ROS time: "
                       "docs/reference/formats_rosbag.md#clocks)"
                     : "");
    }
  } else {
    fmt::print("ground truth  none\n");
  }
}

}  // namespace

void addInfoCommand(CLI::App& app) {
  static InfoOptions options;  // CLI11 binds options to stable addresses; one parse per process
  auto* cmd = app.add_subcommand("info", "Describe a dataset: format, sensor, event count, time span, rates");
  cmd->add_option("--dataset", options.dataset, "ECD-style folder or event file")->required();
  cmd->add_option("--format", options.format, "input format (auto, ecd, mvsec, aevt, evt3, evt2, dat, aedat4, rosbag, dsec)");
  cmd->add_option("--config", options.config, "configuration YAML (sensor size, time tolerance)");
  addSensorOption(cmd, options.sensor);
  addTopicOption(cmd, options.topic);
  addRectifyMapOption(cmd, options.rectify_map);
  addCameraInfoTopicOption(cmd, options.camera_info_topic);
  addGtTopicOption(cmd, options.gt_topic);
  cmd->callback([] { runInfo(options); });
}

}  // namespace asynevo::cli
