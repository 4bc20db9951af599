// 'asynevo track --dataset PATH --out tracks.txt': the frontend alone (DESIGN.md §1). Writes one line
// per feature measurement, "id t x y" (t in seconds, x y raw pixel coordinates), the
// rpg_feature_tracking_analysis format; the lines of one feature are written together, in time order,
// when the feature ends. Frontend statistics go to stdout.
#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/event_reader.hpp"
#include "commands.hpp"
#include "progress.hpp"

namespace asynevo::cli {

namespace {

struct TrackOptions {
  std::string dataset;
  std::string out;
  std::string format = "auto";
  std::string config;
  std::string calib;
};

/// Keeps each active feature's measurements and writes them when the feature ends.
class TrackFileSink final : public frontend::MeasurementSink {
 public:
  explicit TrackFileSink(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "w")) {
    if (!file_) throw InputError(path, "cannot open for writing");
  }
  ~TrackFileSink() override {
    if (file_) std::fclose(file_);
  }
  TrackFileSink(const TrackFileSink&) = delete;
  TrackFileSink& operator=(const TrackFileSink&) = delete;

  void onMeasurement(const TrackMeasurement& m) override { pending_[m.feature_id].push_back(m); }
  void onFeatureEnd(const frontend::FeatureEnd& end) override {
    auto it = pending_.find(end.feature_id);
    if (it == pending_.end()) return;
    char t[32];
    for (const TrackMeasurement& m : it->second) {
      formatNsAsSeconds(m.t_ns, t);
      fmt::print(file_, "{} {} {:.3f} {:.3f}\n", m.feature_id, t, m.x, m.y);
      ++lines_;
    }
    ++tracks_;
    pending_.erase(it);
  }
  void close() {
    const bool failed = std::ferror(file_) != 0;
    const bool close_failed = std::fclose(file_) != 0;
    file_ = nullptr;
    if (failed || close_failed) throw InputError(path_, "write error");
  }
  uint64_t lines() const { return lines_; }
  uint64_t tracks() const { return tracks_; }

 private:
  std::string path_;
  std::FILE* file_;
  std::unordered_map<int64_t, std::vector<TrackMeasurement>> pending_;
  uint64_t lines_ = 0;
  uint64_t tracks_ = 0;
};

void runTrack(const TrackOptions& options) {
  const Config config = options.config.empty() ? Config() : loadConfig(options.config);
  const DatasetFiles files = resolveDataset(options.dataset);
  ReaderOptions reader_options;
  reader_options.format = options.format;
  reader_options.packet_size = config.input.packet_size;
  reader_options.max_time_reversal_ns = std::llround(config.input.max_time_reversal_us * 1e3);
  if (!options.config.empty()) {
    reader_options.width = config.sensor.width;
    reader_options.height = config.sensor.height;
  }
  auto reader = openEventReader(files.events, reader_options);
  const int width = reader->info().width, height = reader->info().height;

  // The undistortion only affects the normalized coordinates, which tracks.txt does not hold; use the
  // calibration when there is one so the frontend runs exactly as in 'asynevo run'.
  UndistortionTable<float> undistortion;
  const std::string calib = !options.calib.empty() ? options.calib : files.calibration.value_or("");
  if (!calib.empty()) undistortion = readCalibration(calib, width, height).undistortionTable<float>();

  frontend::Frontend fe(config.frontend, width, height, std::move(undistortion));
  TrackFileSink sink(options.out);
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
}

}  // namespace

void addTrackCommand(CLI::App& app) {
  static TrackOptions options;  // CLI11 binds options to stable addresses; one parse per process
  auto* cmd = app.add_subcommand("track", "Run the frontend only and write feature tracks");
  cmd->add_option("--dataset", options.dataset, "ECD-style folder or event file")->required();
  cmd->add_option("--out", options.out, "tracks file (id t x y)")->required();
  cmd->add_option("--format", options.format, "input format (auto, ecd, mvsec, aevt)");
  cmd->add_option("--config", options.config, "configuration YAML (frontend section, sensor size)");
  cmd->add_option("--calib", options.calib, "calibration file (default: the dataset's calib.txt, if any)");
  cmd->callback([] { runTrack(options); });
}

}  // namespace asynevo::cli
