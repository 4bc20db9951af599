// 'asynevo track --dataset PATH --out tracks.txt [--eval]': the frontend alone (DESIGN.md §1). Writes
// one line per feature measurement, "id t x y" (t in seconds, x y raw pixel coordinates), the
// rpg_feature_tracking_analysis format. The lines of one feature are written together, in time order,
// and features in increasing id order (= order of creation): a feature is written once it and every
// older feature have ended. Frontend statistics go to stdout. With --eval on a folder written by
// 'asynevo simulate', every track is also compared with its exact ground truth
// (sim/feature_ground_truth.hpp) and the figures are printed.
#include <fmt/format.h>

#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/dataset_reader.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/sim/feature_ground_truth.hpp"
#include "commands.hpp"
#include "progress.hpp"
#include "sensor_option.hpp"

namespace asynevo::cli {

namespace {

struct TrackOptions {
  std::string dataset;
  std::string out;
  std::string format = "auto";
  std::string config;
  std::string calib;
  std::string sensor;
  std::string topic;
  std::string rectify_map;
  bool eval = false;
};

/// Keeps each feature's measurements and writes them, in id order, once the feature and every older one
/// have ended (the frontend numbers features 0, 1, 2, ... and ends each exactly once). Memory: the
/// active features plus the ended ones younger than the oldest active feature.
class TrackFileSink final : public frontend::MeasurementSink {
 public:
  TrackFileSink(const std::string& path, bool keep_all)
      : path_(path), file_(std::fopen(path.c_str(), "w")), keep_all_(keep_all) {
    if (!file_) throw InputError(path, "cannot open for writing");
  }
  ~TrackFileSink() override {
    if (file_) std::fclose(file_);
  }
  TrackFileSink(const TrackFileSink&) = delete;
  TrackFileSink& operator=(const TrackFileSink&) = delete;

  void onMeasurement(const TrackMeasurement& m) override {
    pending_[m.feature_id].measurements.push_back(m);
    if (keep_all_) all_.push_back(m);
  }
  void onFeatureEnd(const frontend::FeatureEnd& end) override {
    pending_[end.feature_id].ended = true;
    // Write every ended feature from the oldest not yet written on.
    for (auto it = pending_.begin(); it != pending_.end() && it->first == next_id_ && it->second.ended;
         it = pending_.erase(it), ++next_id_) {
      if (it->second.measurements.empty()) continue;
      char t[32];
      for (const TrackMeasurement& m : it->second.measurements) {
        formatNsAsSeconds(m.t_ns, t);
        fmt::print(file_, "{} {} {} {}\n", m.feature_id, t, m.x, m.y);  // shortest exact float text
        ++lines_;
      }
      ++tracks_;
    }
  }
  void close() {
    const bool failed = std::ferror(file_) != 0;
    const bool close_failed = std::fclose(file_) != 0;
    file_ = nullptr;
    if (failed || close_failed) throw InputError(path_, "write error");
  }
  uint64_t lines() const { return lines_; }
  uint64_t tracks() const { return tracks_; }
  /// Every measurement (only with keep_all).
  const std::vector<TrackMeasurement>& all() const { return all_; }

 private:
  struct Pending {
    std::vector<TrackMeasurement> measurements;
    bool ended = false;
  };
  std::string path_;
  std::FILE* file_;
  bool keep_all_;
  std::map<int64_t, Pending> pending_;
  int64_t next_id_ = 0;
  std::vector<TrackMeasurement> all_;
  uint64_t lines_ = 0;
  uint64_t tracks_ = 0;
};

void runTrack(const TrackOptions& options) {
  Config config = options.config.empty() ? Config() : loadConfig(options.config);
  const DatasetFiles files = resolveDataset(options.dataset, options.format);
  // The ground truth first: a dataset that cannot be evaluated fails before the (long) run.
  std::optional<sim::FeatureGroundTruth> ground_truth;
  if (options.eval) {
    if (!sim::isSimulatedDataset(files.root))
      throw InputError(options.dataset,
                       "--eval needs a folder written by 'asynevo simulate' (sim.yaml and groundtruth.txt)");
    ground_truth.emplace(sim::loadSimulatedGroundTruth(files.root));
  }
  std::vector<std::string> notes;
  const ReaderOptions reader_options = datasetReaderOptions(
      files, config,
      {options.format, options.sensor, options.calib, options.config, options.topic, options.rectify_map},
      &notes);
  for (const std::string& note : notes) fmt::print("note: {}\n", note);
  auto reader = openEventReader(files.events, reader_options);
  const int width = reader->info().width, height = reader->info().height;
  config.sensor.width = width;
  config.sensor.height = height;
  config.validateForSensor();

  // The undistortion only affects the normalized coordinates, which tracks.txt does not hold; use the
  // calibration when there is one so the frontend runs exactly as in 'asynevo run'.
  UndistortionTable<float> undistortion;
  const std::string calib = !options.calib.empty() ? options.calib : files.calibration.value_or("");
  if (!calib.empty()) undistortion = readCalibration(calib, width, height).undistortionTable<float>();

  frontend::Frontend fe(config.frontend, width, height, std::move(undistortion));
  TrackFileSink sink(options.out, options.eval);
  EventPacket packet;
  Progress progress;
  uint64_t events = 0;
  int64_t first_t_ns = 0;
  while (reader->read(packet)) {
    if (events == 0) first_t_ns = packet.frontTime();
    fe.process(packet, sink);
    events += packet.size();
    progress.update(events, packet.backTime(), first_t_ns);
  }
  progress.finish();
  fe.finish(sink);
  sink.close();
  fmt::print("{}", fe.stats().summary());
  fmt::print("wrote             {} lines, {} tracks to {}\n", sink.lines(), sink.tracks(), options.out);
  if (!reader->info().rectify_map.empty())
    fmt::print("rectified         by {}: {} events mapped outside the sensor, dropped\n",
               reader->info().rectify_map, reader->stats().rectified_outside);
  if (ground_truth) {
    fmt::print("{}", sim::evaluateFeatureTracks(sink.all(), *ground_truth).summary());
  }
}

}  // namespace

void addTrackCommand(CLI::App& app) {
  static TrackOptions options;  // CLI11 binds options to stable addresses; one parse per process
  auto* cmd = app.add_subcommand("track", "Run the frontend only and write feature tracks");
  cmd->add_option("--dataset", options.dataset, "ECD-style folder or event file")->required();
  cmd->add_option("--out", options.out, "tracks file (id t x y)")->required();
  cmd->add_option("--format", options.format, "input format (auto, ecd, mvsec, aevt, evt3, evt2, dat, aedat4, rosbag, dsec)");
  cmd->add_option("--config", options.config, "configuration YAML (frontend section, sensor size)");
  cmd->add_option("--calib", options.calib, "calibration file (default: the dataset's calib.txt, if any)");
  addSensorOption(cmd, options.sensor);
  addTopicOption(cmd, options.topic);
  addRectifyMapOption(cmd, options.rectify_map);
  cmd->add_flag("--eval", options.eval,
                "simulated datasets ('asynevo simulate' folders): compare every track with its exact ground "
                "truth and print the errors");
  cmd->callback([] { runTrack(options); });
}

}  // namespace asynevo::cli
