#include "asynevo/pipeline/run_frames.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>

#include "asynevo/core/error.hpp"
#include "asynevo/frames/frame_folder.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/groundtruth_reader.hpp"

namespace asynevo::pipeline {

namespace {

/// --calib, else the folder's calib.txt, else its camchain.yaml.
std::string frameFolderCalibration(const FramesRunOptions& options) {
  if (!options.calib.empty()) return options.calib;
  const std::filesystem::path dir(options.frames);
  for (const char* name : {"calib.txt", "camchain.yaml"})
    if (std::filesystem::is_regular_file(dir / name)) return (dir / name).string();
  throw InputError(options.frames,
                   "no camera calibration: the frame folder has no calib.txt or camchain.yaml; "
                   "pass --calib FILE");
}

void drain(backend::Estimator& estimator, RunFolderWriter& writer) {
  auto knots = estimator.takeFinalKnots();
  if (!knots.empty()) writer.onFinalKnots(knots);
  auto records = estimator.takeUpdateRecords();
  if (!records.empty()) writer.onUpdateRecords(records);
  auto landmarks = estimator.takeFinalLandmarks();
  if (!landmarks.empty()) writer.onLandmarks(landmarks);
}

}  // namespace

RunSummary runFrameFolder(const FramesRunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  RunSummary summary;
  summary.out_dir = options.out;
  Config config = options.config_path.empty() ? Config() : loadConfig(options.config_path);
  const std::vector<frames::FrameEntry> frame_list = frames::readFrameList(options.frames);
  const std::string calib = frameFolderCalibration(options);
  const cv::Mat first = frames::loadFrame(frame_list.front());
  summary.dataset_events = (std::filesystem::path(options.frames) / "images.txt").string();
  summary.format = "frames";
  summary.width = first.cols;
  summary.height = first.rows;
  summary.size_origin = "the first frame";
  config.sensor.width = summary.width;
  config.sensor.height = summary.height;
  config.validate();
  const CameraModel camera = readCalibration(calib, summary.width, summary.height);
  summary.calibration = calib;
  if (camera.width() != summary.width || camera.height() != summary.height)
    throw InputError(calib, fmt::format("calibration is for {}x{} pixels but the frames are {}x{}",
                                        camera.width(), camera.height(), summary.width, summary.height));
  summary.config = config;

  RunFolderWriter writer(options.out);
  writer.writeConfig(config);
  backend::EstimatorOptions estimator_options;
  estimator_options.config = config.backend;
  estimator_options.focal_px = 0.5 * (camera.fx() + camera.fy());
  const std::unique_ptr<backend::Estimator> estimator = makeEstimator(options.backend, estimator_options);
  summary.backend_name = estimator->name();

  frames::KltTracker tracker(camera, options.klt);
  constexpr int64_t kMarkerPeriodNs = 1'000'000;
  PipelineStats& p = summary.pipeline;
  p.first_t_ns = frame_list.front().t_ns;
  p.last_t_ns = frame_list.back().t_ns;
  // The first marker: the first multiple of the period after the first frame (as MarkerClock).
  int64_t next_marker = (p.first_t_ns / kMarkerPeriodNs) * kMarkerPeriodNs + kMarkerPeriodNs;
  for (const frames::FrameEntry& frame : frame_list) {
    // Markers at every 1 ms up to the frame's time, as the event pipeline sends them between events.
    for (; next_marker <= frame.t_ns; next_marker += kMarkerPeriodNs) {
      writer.onMarker(next_marker);
      estimator->advanceTo(next_marker);
      drain(*estimator, writer);
      ++p.markers;
    }
    const frames::KltFrameResult result =
        tracker.track(frame.t_ns, frames::loadFrame(frame, summary.width, summary.height));
    for (int64_t id : result.ended) {
      estimator->endFeature(id);
      ++p.feature_ends;
    }
    for (const TrackMeasurement& m : result.measurements) {
      writer.onMeasurement(m);
      estimator->addMeasurement(m);
    }
    p.measurements += result.measurements.size();
    summary.frontend.measurements += result.measurements.size();
    summary.frontend.max_active_features =
        std::max(summary.frontend.max_active_features, static_cast<int>(tracker.activeFeatures()));
    ++p.packets;
  }
  estimator->finish();
  drain(*estimator, writer);
  writer.close();
  p.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.frontend.features_created = tracker.featuresCreated();
  summary.estimator = estimator->stats();
  summary.update_time = writer.updateTimeStats();
  summary.knots_written = writer.knotsWritten();
  summary.landmarks_written = writer.landmarksWritten();
  summary.measurements_written = writer.measurementsWritten();

  const std::filesystem::path gt_path = std::filesystem::path(options.frames) / "groundtruth.txt";
  if (std::filesystem::is_regular_file(gt_path)) {
    StampedTrajectory span;
    for (const StampedPose& pose : readGroundTruth(gt_path.string()))
      if (pose.t_ns >= p.first_t_ns && pose.t_ns <= p.last_t_ns) span.push_back(pose);
    if (!span.empty()) {
      writer.writeGroundTruth(span);
      summary.groundtruth = gt_path.string();
      summary.groundtruth_poses = span.size();
    }
  }
  summary.peak_memory_mb = peakMemoryMb();
  RunOptions run_options;
  run_options.dataset = options.frames;
  run_options.format = "frames";
  writer.writeText("stats.json", runStatsJson(summary, run_options) + "\n");
  return summary;
}

}  // namespace asynevo::pipeline
