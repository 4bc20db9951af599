#include "asynevo/pipeline/run.hpp"

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "asynevo/backend/incremental_estimator.hpp"
#include "asynevo/backend/sliding_window_estimator.hpp"
#include "asynevo/backend/triangulation.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/dataset_reader.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/groundtruth_reader.hpp"
#include "asynevo/io/rosbag_topics.hpp"
#include "asynevo/io/repeat_reader.hpp"
#include "asynevo/io/skip_reader.hpp"

namespace asynevo::pipeline {

std::optional<BackendKind> parseBackendKind(const std::string& name) {
  if (name == "window") return BackendKind::kWindow;
  if (name == "incremental") return BackendKind::kIncremental;
  if (name == "incremental-frozen") return BackendKind::kIncrementalFrozen;
  return std::nullopt;
}

std::unique_ptr<backend::Estimator> makeEstimator(BackendKind kind, const backend::EstimatorOptions& options) {
  if (kind == BackendKind::kWindow) return std::make_unique<backend::SlidingWindowEstimator>(options);
  backend::IncrementalOptions incremental;  // the full-history smoother baselines (docs/backend.md)
  incremental.frozen = kind == BackendKind::kIncrementalFrozen;
  return std::make_unique<backend::IncrementalEstimator>(options, incremental);
}

double peakMemoryMb() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

namespace {

std::string pixelList(const std::vector<std::pair<int, int>>& pixels, std::size_t at_most) {
  std::string s;
  for (std::size_t i = 0; i < std::min(pixels.size(), at_most); ++i)
    s += fmt::format("{}({}, {})", i ? " " : "", pixels[i].first, pixels[i].second);
  return pixels.size() > at_most ? s + " ..." : s;
}

/// Warnings about sensor noise: pixels the hot-pixel filter masked, and a stream where a few pixels
/// sent more than half of the events (hot pixels or a flickering light, filtered or not).
void noiseWarnings(const frontend::Frontend& fe, std::vector<std::string>& warnings) {
  const auto hot = fe.hotPixels();
  if (!hot.empty())
    warnings.push_back(fmt::format("the hot-pixel filter masked {} pixel(s): {}", hot.size(), pixelList(hot, 10)));
  const auto dominant = fe.dominantPixels(0.5, 16);
  if (dominant.empty()) return;
  std::string list;
  for (const auto& p : dominant) list += fmt::format("{}({}, {}) {} events", list.empty() ? "" : ", ", p.x, p.y, p.events);
  warnings.push_back(fmt::format(
      "more than half of the events came from {} pixel(s): {} (hot pixels or a flickering light; "
      "frontend.hot_pixel_filter masks hot pixels)",
      dominant.size(), list));
}

/// Hands every output to the run-folder writer and, when there is one, to an observer (same order).
class TeeOutput final : public PipelineOutput {
 public:
  TeeOutput(PipelineOutput& first, PipelineOutput* second) : first_(first), second_(second) {}
  void onMeasurement(const TrackMeasurement& m) override {
    first_.onMeasurement(m);
    if (second_) second_->onMeasurement(m);
  }
  void onMarker(int64_t t_ns) override {
    first_.onMarker(t_ns);
    if (second_) second_->onMarker(t_ns);
  }
  void onFinalKnots(const std::vector<backend::Knot>& knots) override {
    first_.onFinalKnots(knots);
    if (second_) second_->onFinalKnots(knots);
  }
  void onUpdateRecords(const std::vector<backend::UpdateRecord>& records) override {
    first_.onUpdateRecords(records);
    if (second_) second_->onUpdateRecords(records);
  }
  void onLandmarks(const std::vector<backend::LandmarkPoint>& landmarks) override {
    first_.onLandmarks(landmarks);
    if (second_) second_->onLandmarks(landmarks);
  }

 private:
  PipelineOutput& first_;
  PipelineOutput* second_;
};

}  // namespace

std::unique_ptr<backend::Estimator> makeEstimator(BackendKind kind, const Config& config,
                                                  const CameraModel& camera, const frontend::Frontend& fe,
                                                  bool real_time) {
  backend::EstimatorOptions estimator_options;
  estimator_options.config = config.backend;
  // Pixel thresholds of the backend are in the frontend's (binned) pixels, like its measurements' noise.
  estimator_options.focal_px = 0.5 * (camera.fx() + camera.fy()) / fe.binning();
  estimator_options.real_time = real_time;
  return makeEstimator(kind, estimator_options);
}

void runEvents(EventReader& reader, const CameraModel& camera, const Config& config,
               const RunOptions& options, RunFolderWriter& writer, RunSummary& summary,
               const std::function<void(const PipelineProgress&)>& progress, PipelineOutput* observer) {
  writer.writeConfig(config);
  frontend::Frontend fe(config.frontend, camera);
  std::unique_ptr<backend::Estimator> estimator_ptr =
      makeEstimator(options.backend, config, camera, fe, options.real_time);
  backend::Estimator& estimator = *estimator_ptr;
  summary.backend_name = estimator.name();

  PipelineOptions pipeline_options;
  pipeline_options.real_time = options.real_time;
  pipeline_options.speed = options.speed;
  TeeOutput tee(writer, observer);
  Pipeline pipeline(reader, fe, estimator, tee, pipeline_options);
  summary.pipeline = pipeline.run(progress);
  writer.close();

  summary.frontend = fe.stats();
  summary.hot_pixels = fe.hotPixels();
  noiseWarnings(fe, summary.warnings);
  summary.estimator = estimator.stats();
  summary.update_time = writer.updateTimeStats();
  summary.knots_written = writer.knotsWritten();
  summary.landmarks_written = writer.landmarksWritten();
  summary.measurements_written = writer.measurementsWritten();
}

namespace {

/// --gt-camera-clock (docs/reference/formats_rosbag.md#clocks): the bag's poses carry ROS time, its
/// EventPacket events the camera's clock; the first packet's header stamp is taken as the ROS time of its
/// first event, and the poses are shifted by the difference.
void shiftToCameraClock(DatasetGroundTruth& gt, const std::string& bag, const EventReader& reader,
                        RunSummary& summary) {
  if (gt.source.rfind(bag + " (topic ", 0) != 0) {
    throw InputError(gt.source, "--gt-camera-clock shifts a bag's pose topic; this ground truth is a file (its "
                                "times are used as they are)");
  }
  std::optional<int64_t> stamp;
  for (const ContainerStream& stream : reader.stats().streams)
    if (stream.delivered && !stamp) stamp = rosbagFirstPacketStamp(bag, stream.name);
  if (!stamp) {
    summary.warnings.push_back("--gt-camera-clock: the events are no event_camera_msgs/EventPacket topic; their "
                               "times are ROS time already, so the poses are not shifted");
    return;
  }
  const int64_t shift = summary.pipeline.first_t_ns - *stamp;
  for (StampedPose& p : gt.poses) p.t_ns += shift;
  summary.groundtruth_shift_s = nsToSeconds(shift);
  gt.source += fmt::format(", shifted by {:.9f} s onto the events' camera clock", nsToSeconds(shift));
}

}  // namespace

RunSummary runDataset(const RunOptions& options, const std::function<void(const PipelineProgress&)>& progress,
                      PipelineOutput* observer) {
  RunSummary summary;
  summary.out_dir = options.out;

  // Everything that can be checked before reading events is checked first.
  Config config = options.config ? *options.config
                                 : (options.config_path.empty() ? Config() : loadConfig(options.config_path));
  const DatasetFiles files = resolveDataset(options.dataset, options.format);
  // --calib, --camera-info-topic, a file beside the events, a ROS bag's CameraInfo topic
  // (chooseDatasetCalibration).
  const DatasetCalibration calibration =
      chooseDatasetCalibration(files, options.calib, options.camera_info_topic, options.topic);
  const std::string& calib = calibration.file;
  const std::optional<BagCalibration>& bag_calib = calibration.bag;
  if (bag_calib && !calibration.note.empty()) summary.warnings.push_back("calibration: " + calibration.note);
  const bool bag = isRosbag(files.events);
  if (calib.empty() && !bag_calib)
    throw InputError(files.root,
                     std::string("no camera calibration: the dataset folder has no calib.txt or Kalibr camchain .yaml") +
                         (bag ? " and the bag no sensor_msgs/CameraInfo topic" : "") + "; pass --calib FILE");
  checkGroundTruthChoice(files, options.gt_topic);
  if (options.gt_camera_clock && !bag)
    throw ConfigError(fmt::format("--gt-camera-clock applies to ROS bags of event_camera_msgs/EventPacket events; {} "
                                  "is not a ROS bag",
                                  files.events));

  // The sensor size by precedence: --sensor, the configuration's sensor block, sensor.yaml, a camchain's
  // resolution, the format (io/sensor_size.hpp).
  const ReaderOptions reader_options =
      datasetReaderOptions(files, config,
                           {options.format, options.sensor, options.calib, options.config_path, options.topic,
                            options.rectify_map},
                           &summary.warnings);
  if (options.repeat < 1) throw ConfigError(fmt::format("--repeat must be at least 1, not {}", options.repeat));
  if (!(options.skip_ms >= 0 && options.skip_ms <= 1e12))  // 1e12 ms: 31 years, far inside int64 ns
    throw ConfigError(fmt::format("--skip-ms must be a duration from 0 to 1e12 ms, not {}", options.skip_ms));
  std::unique_ptr<EventReader> reader = skipStartOfStream(
      options.repeat == 1
          ? openEventReader(files.events, reader_options)
          : repeatEvents([&] { return openEventReader(files.events, reader_options); }, options.repeat),
      std::llround(options.skip_ms * 1e6));
  summary.dataset_events = files.events;
  summary.format = reader->info().format;
  summary.width = reader->info().width;
  summary.height = reader->info().height;
  summary.size_origin = reader->info().size_origin;
  summary.rectify_map = reader->info().rectify_map;
  config.sensor.width = summary.width;
  config.sensor.height = summary.height;
  config.validate();
  config.validateForSensor();
  summary.config = config;

  const CameraModel camera = bag_calib ? bag_calib->camera : readCalibration(calib, summary.width, summary.height);
  summary.calibration = bag_calib ? bagTopicSource(files.events, bag_calib->topic) : calib;
  if (camera.width() != summary.width || camera.height() != summary.height) {
    if (bag_calib) {
      throw InputError(files.events,
                       fmt::format("the camera info of topic {} is for {}x{} pixels but the events are {}x{} (size "
                                   "from {}); pass the right calibration with --calib FILE",
                                   bag_calib->topic, camera.width(), camera.height(), summary.width, summary.height,
                                   summary.size_origin));
    }
    throw InputError(
        calib, fmt::format("calibration is for {}x{} pixels but the events ({}) are {}x{} (size from {})",
                           camera.width(), camera.height(), files.events, summary.width, summary.height,
                           summary.size_origin));
  }

  // Rectified events (DSEC's rectify_map.h5) are pixels of the rectified camera, which has no distortion: a
  // distorted calibration is the raw camera's (docs/reference/formats.md#rectification).
  const std::vector<double>& coefficients = camera.coefficients();
  const bool distorted = camera.distortionModel() != DistortionModel::kNone &&
                         std::any_of(coefficients.begin(), coefficients.end(), [](double c) { return c != 0.0; });
  if (!summary.rectify_map.empty() && distorted) {
    summary.warnings.push_back(fmt::format(
        "the events are rectified by {} but the calibration {} has {} distortion: rectified events need "
        "DSEC's rectified camera (cam_to_cam.yaml intrinsics camRect0 or camRect3, no distortion), or "
        "--rectify-map none for the raw camera",
        summary.rectify_map, summary.calibration, distortionModelName(camera.distortionModel())));
  }

  // Outputs that do not depend on the run come first: a failed run still says how it was configured.
  RunFolderWriter writer(options.out);
  runEvents(*reader, camera, config, options, writer, summary, progress, observer);
  const ReaderStats& reader_stats = reader->stats();
  summary.rectified_outside = reader_stats.rectified_outside;
  summary.events_skipped_at_start = reader_stats.skipped_at_start;

  // The ground truth: --gt-topic, else a file beside the events, else a bag's only pose topic
  // (loadDatasetGroundTruth). Problems are warnings: the estimate is written either way.
  try {
    std::optional<DatasetGroundTruth> gt = loadDatasetGroundTruth(files, options.gt_topic);
    if (gt && options.gt_camera_clock) shiftToCameraClock(*gt, files.events, *reader, summary);
    if (gt) {
      summary.groundtruth = gt->source;
      if (!gt->note.empty()) summary.warnings.push_back("ground truth from " + gt->source + "; " + gt->note);
    }
    if (gt && options.repeat > 1) {
      summary.warnings.push_back(fmt::format("ground truth not written: the stream was played {} times (--repeat)",
                                             options.repeat));
    } else if (gt) {
      StampedTrajectory span;
      for (const StampedPose& p : gt->poses)
        if (p.t_ns >= summary.pipeline.first_t_ns && p.t_ns <= summary.pipeline.last_t_ns) span.push_back(p);
      if (span.empty()) {
        summary.warnings.push_back(fmt::format(
            "{}: no ground-truth pose within the event time span ({:.3f} .. {:.3f} s; poses {:.3f} .. {:.3f} s){}; "
            "stamped_groundtruth.txt not written",
            gt->source, nsToSeconds(summary.pipeline.first_t_ns), nsToSeconds(summary.pipeline.last_t_ns),
            nsToSeconds(gt->poses.front().t_ns), nsToSeconds(gt->poses.back().t_ns),
            bag && !options.gt_camera_clock
                ? " (a bag's EventPacket events carry the camera's clock, its poses ROS time: --gt-camera-clock "
                  "shifts the poses, docs/reference/formats_rosbag.md#clocks)"
                : ""));
      } else {
        writer.writeGroundTruth(span);
        summary.groundtruth_poses = span.size();
      }
    }
  } catch (const InputError& e) {
    summary.warnings.push_back(std::string("ground truth skipped: ") + e.what());
  }
  summary.peak_memory_mb = peakMemoryMb();
  if (!summary.estimator.segments.empty())
    writer.writeText("segments.txt", backend::segmentsFileText(summary.estimator.segments));
  if (!summary.estimator.init_attempt_log.empty())
    writer.writeText("init_attempts.txt", backend::initAttemptsFileText(summary.estimator.init_attempt_log,
                                                                      summary.estimator.init_attempts_not_logged));
  if (!summary.estimator.init_reversal_log.empty())
    writer.writeText("init_reversals.txt", backend::initReversalsFileText(summary.estimator.init_reversal_log));
  writer.writeText("stats.json", runStatsJson(summary, options) + "\n");
  return summary;
}

std::string initializationFailureMessage(const RunSummary& s) {
  const auto& e = s.estimator;
  return fmt::format(
      "initialization never succeeded after {} attempt(s): {}\n"
      "  counts: {} events over {:.3f} s, {} features created, {} measurements sent to the backend, "
      "at most {} features active at once\n"
      "  a textured scene and enough camera motion (parallax) are needed; init_attempts.txt in the run "
      "folder says why each attempt failed; see docs/pipeline.md",
      e.init_attempts,
      e.init_last_failure.empty() ? "no attempt was possible (too few measurements)" : e.init_last_failure,
      s.pipeline.events, s.pipeline.spanSeconds(), s.frontend.features_created, e.measurements_received,
      s.frontend.max_active_features);
}

std::string runSummaryText(const RunSummary& s) {
  std::string t;
  const auto& p = s.pipeline;
  const auto& e = s.estimator;
  t += fmt::format("events          {} over {:.3f} s ({}, {}x{}){}\n", p.events, p.spanSeconds(), s.format,
                   s.width, s.height,
                   s.events_skipped_at_start > 0
                       ? fmt::format("; {} before them skipped (--skip-ms)", s.events_skipped_at_start)
                       : "");
  t += fmt::format("frontend        {} features, {} measurements, {:.1f} active on average\n",
                   s.frontend.features_created, s.frontend.measurements, s.frontend.meanActiveFeatures());
  t += fmt::format(
      "backend         {}: {} knots written, {} landmarks, {} marginalizations ({} knots), "
      "window <= {} knots\n",
      s.backend_name, s.knots_written, s.landmarks_written, e.marginalizations, e.knots_marginalized,
      e.max_window_knots);
  if (e.initialized)
    t += fmt::format("initialized     at t = {:.3f} s after {} attempt(s), {}\n",
                     nsToSeconds(e.initialized_at_ns), e.init_attempts,
                     backend::describeInitViews(e.init_views));
  if (e.segments.size() > 1) {
    std::string list;
    for (const backend::Segment& seg : e.segments) {
      list += fmt::format("{}{:.2f}-{:.2f} s ({})", list.empty() ? "" : ", ", nsToSeconds(seg.t0_ns),
                          nsToSeconds(seg.t1_ns), backend::segmentEndName(seg.end));
    }
    t += fmt::format("segments        {}: {}; {} window knots dropped at a loss\n", e.segments.size(), list,
                     e.knots_dropped_at_loss);
  }
  t +=
      fmt::format("update time     median {:.2f} ms, p95 {:.2f} ms, max {:.2f} ms over {} updates\n",
                  s.update_time.median_ms, s.update_time.p95_ms, s.update_time.max_ms, s.update_time.updates);
  t += fmt::format("wall time       {:.2f} s, real-time factor {:.2f} ({}), peak memory {:.0f} MiB\n",
                   p.wall_seconds, p.realTimeFactor(), p.real_time ? "real-time mode" : "offline",
                   s.peak_memory_mb);
  if (p.real_time)
    t += fmt::format("backend lag     max {:.3f} s, mean {:.3f} s\n", p.max_lag_ns * 1e-9,
                     p.mean_lag_ns * 1e-9);
  if (!s.calibration.empty()) t += fmt::format("calibration     {}\n", s.calibration);
  if (!s.rectify_map.empty())
    t += fmt::format("rectified       by {}: {} events mapped outside the sensor, dropped\n", s.rectify_map,
                     s.rectified_outside);
  if (!s.groundtruth.empty())
    t += fmt::format("ground truth    {} ({} poses in the event span written)\n", s.groundtruth,
                     s.groundtruth_poses.value_or(0));
  for (const std::string& w : s.warnings) t += "warning: " + w + "\n";
  t += fmt::format("run folder      {}\n", s.out_dir);
  return t;
}

std::string runStatsJson(const RunSummary& s, const RunOptions& options) {
  const auto& p = s.pipeline;
  const auto& e = s.estimator;
  const auto& f = s.frontend;

  JsonObject input;
  input.add("dataset", options.dataset)
      .add("events_file", s.dataset_events)
      .add("format", s.format)
      .add("width", s.width)
      .add("height", s.height)
      .add("size_origin", s.size_origin)
      .add("rectify_map", s.rectify_map)
      .add("rectified_outside", s.rectified_outside)
      .add("calibration", s.calibration)
      .add("groundtruth", s.groundtruth)
      .add("groundtruth_shift_s", s.groundtruth_shift_s)
      .add("first_event_s", nsToSeconds(p.first_t_ns))
      .add("last_event_s", nsToSeconds(p.last_t_ns))
      .add("groundtruth_poses", static_cast<uint64_t>(s.groundtruth_poses.value_or(0)))
      .add("repeat", options.repeat)
      .add("skip_ms", options.skip_ms)
      .add("events_skipped_at_start", s.events_skipped_at_start);

  JsonObject frontend;
  frontend.add("events", f.events)
      .add("dropped_out_of_sensor", f.dropped_out_of_sensor)
      .add("dropped_time_reversal", f.dropped_time_reversal)
      .add("clamped_time", f.clamped_time)
      .add("dropped_hot_pixel", f.dropped_hot_pixel)
      .add("dropped_noise_filter", f.dropped_noise_filter)
      .add("events_shed", f.events_shed)
      .add("detections_skipped", f.detections_skipped)
      .add("hot_pixels", static_cast<uint64_t>(s.hot_pixels.size()))
      .add("filter_accepted", f.filter_accepted)
      .add("detector_runs", f.detector_runs)
      .add("candidates", f.candidates)
      .add("corners", f.corners)
      .add("tracker_updates", f.tracker_updates)
      .add("state_changes", f.state_changes)
      .add("measurements", f.measurements)
      .add("measurements_without_undistortion", f.measurements_without_undistortion)
      .add("events_without_position", f.events_without_position)
      .add("subpixel_fit_failures", f.subpixel_fit_failures)
      .add("features_created", f.features_created)
      .add("max_active_features", f.max_active_features)
      .add("harris_threshold_end", f.harris_threshold)
      .add("harris_threshold_min", f.min_harris_threshold)
      .add("mean_active_features", f.meanActiveFeatures())
      .add("median_active_features", f.activeFeaturesQuantile(0.5));
  JsonObject dropped;
  for (int i = 0; i < frontend::kDropReasonCount; ++i)
    dropped.add(frontend::dropReasonName(static_cast<frontend::DropReason>(i)),
                f.features_dropped[static_cast<std::size_t>(i)]);
  frontend.addObject("features_dropped", dropped);

  JsonObject estimator;
  estimator.add("name", s.backend_name)
      .add("initialized", e.initialized)
      .add("initialized_at_s", e.initialized ? nsToSeconds(e.initialized_at_ns) : 0.0)
      .add("init_attempts", e.init_attempts)
      .add("init_last_failure", e.init_last_failure)
      .add("init_method", e.init_views.method)
      .add("init_rotation_refits", e.init_rotation_refits)
      .add("init_retriangulations", e.init_retriangulations)
      .add("init_two_view_landmark_starts", e.init_two_view_landmark_starts)
      .add("init_weak_two_view_replaced", e.init_weak_two_view_replaced)
      .add("init_depth_reversed", e.init_depth_reversed)
      .add("direction_audits", e.direction_audits)
      .add("direction_audit_votes", e.direction_audit_votes)
      .add("init_relaxed_again", e.init_relaxed_again)
      .add("init_restarts_relaxed", e.init_restarts_relaxed)
      .add("init_span_ms", e.init_views.span_ms)
      .add("init_features", e.init_views.features)
      .add("init_inliers", e.init_views.inliers)
      .add("init_parallax_px", e.init_views.parallax_px)
      .add("init_landmarks", e.init_views.landmarks)
      .add("measurements_received", e.measurements_received)
      .add("measurements_before_window", e.measurements_before_window)
      .add("measurements_out_of_order", e.measurements_out_of_order)
      .add("measurements_subsampled", e.measurements_subsampled)
      .add("knots", e.knots)
      .add("updates", e.updates)
      .add("landmarks_created", e.landmarks_created);
  JsonObject rejections;  // failed attempts by the furthest check they reached ("none" is never counted)
  for (int i = 1; i < backend::kInitRejections; ++i)
    rejections.add(backend::rejectionName(static_cast<backend::InitRejection>(i)),
                   e.init_rejections[static_cast<std::size_t>(i)]);
  estimator.addObject("init_rejections", rejections);
  JsonObject tri;
  for (int i = 0; i < backend::kTriangulationFailureCount; ++i)
    tri.add(backend::triangulationFailureName(static_cast<backend::TriangulationFailure>(i)),
            e.triangulation_failures[static_cast<std::size_t>(i)]);
  estimator.addObject("triangulation_failures", tri)
      .add("marginalizations", e.marginalizations)
      .add("knots_marginalized", e.knots_marginalized)
      .add("landmarks_marginalized", e.landmarks_marginalized)
      .add("forced_marginalizations", e.forced_marginalizations)
      .add("observations_dropped_forced", e.observations_dropped_forced)
      .add("observations_fixed_pose", e.observations_fixed_pose)
      .add("observations_marginalized", e.observations_marginalized)
      .add("landmarks_released", e.landmarks_released)
      .add("observations_dropped_untriangulated", e.observations_dropped_untriangulated)
      .add("outliers_removed", e.outliers_removed)
      .add("tracks_rejected", e.tracks_rejected)
      .add("tracks_split", e.tracks_split)
      .add("landmarks_rejoined", e.landmarks_rejoined)
      .add("rejoins_ambiguous", e.rejoins_ambiguous)
      .add("measurements_of_superseded_features", e.measurements_of_superseded_features)
      .add("measurements_of_rejected_tracks", e.measurements_of_rejected_tracks)
      .add("landmarks_lost", e.landmarks_lost)
      .add("landmarks_depth_rejected", e.landmarks_depth_rejected)
      .add("landmarks_depth_reset", e.landmarks_depth_reset)
      .add("scale_anchors", e.scale_anchors)
      .add("knots_dropped_at_loss", e.knots_dropped_at_loss)
      .add("measurements_before_reset", e.measurements_before_reset)
      .add("measurements_non_finite", e.measurements_non_finite)
      .add("max_median_residual_px", e.max_median_residual_px)
      .add("max_depth_ratio", e.max_depth_ratio)
      .add("max_window_knots", e.max_window_knots)
      .add("last_prior_rank", e.last_prior_rank);

  std::vector<JsonObject> segments;
  for (const backend::Segment& seg : e.segments) {
    JsonObject o;
    o.add("initialized_at_s", nsToSeconds(seg.initialized_at_ns))
        .add("start_s", nsToSeconds(seg.t0_ns))
        .add("end_s", nsToSeconds(seg.t1_ns))
        .add("knots", seg.knots)
        .add("ended_at_s", nsToSeconds(seg.ended_at_ns))
        .add("ended_by", backend::segmentEndName(seg.end));
    segments.push_back(o);
  }
  estimator.addArray("segments", segments);

  JsonObject update;
  update.add("updates", s.update_time.updates)
      .add("median_ms", s.update_time.median_ms)
      .add("p95_ms", s.update_time.p95_ms)
      .add("max_ms", s.update_time.max_ms)
      .add("mean_ms", s.update_time.mean_ms);

  JsonObject pipe;
  pipe.add("mode", p.real_time ? "real-time" : "offline")
      .add("speed", options.speed)
      .add("markers", p.markers)
      .add("packets", p.packets)
      .add("feature_ends", p.feature_ends)
      .add("queue_capacity_chunks", static_cast<uint64_t>(p.queue_capacity))
      .add("queue_high_water_chunks", static_cast<uint64_t>(p.queue_high_water))
      .add("queue_push_waits", p.queue_push_waits)
      .add("queue_pop_waits", p.queue_pop_waits)
      .add("frontend_thread_s", p.frontend_seconds)
      .add("backend_busy_s", p.backend_busy_seconds)
      .add("backend_lag_max_s", p.max_lag_ns * 1e-9)
      .add("backend_lag_mean_s", p.mean_lag_ns * 1e-9)
      .add("pacing_max_behind_s", p.max_pacing_behind_ns * 1e-9);

  JsonObject root;
  root.add("asynevo_version", "0.1.0")
      .add("backend", s.backend_name)
      .add("config_digest", configDigest(s.config))
      .add("initialized", e.initialized)
      .add("segments", static_cast<uint64_t>(e.segments.size()))
      .add("events", p.events)
      .add("event_time_span_s", p.spanSeconds())
      .add("features", f.features_created)
      .add("measurements", s.measurements_written)
      .add("knots", s.knots_written)
      .add("landmarks", s.landmarks_written)
      .add("marginalizations", e.marginalizations)
      .add("wall_time_s", p.wall_seconds)
      .add("real_time_factor", p.realTimeFactor())
      .add("peak_memory_mb", s.peak_memory_mb)
      .addObject("input", input)
      .addObject("pipeline", pipe)
      .addObject("update_time", update)
      .addObject("frontend", frontend)
      .addObject("estimator", estimator);
  return root.str();
}

}  // namespace asynevo::pipeline
