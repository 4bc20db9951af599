#pragma once
// One call from a dataset to a run folder: what 'asynevo run' does (DESIGN.md §1). Resolves the
// dataset, loads the configuration and the calibration (an error before any processing when there is
// none), builds the reader, frontend and estimator, runs the two-thread pipeline and writes the run
// folder (docs/pipeline.md).

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "asynevo/backend/estimator.hpp"
#include "asynevo/backend/sliding_window_estimator.hpp"
#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/pipeline/pipeline.hpp"
#include "asynevo/pipeline/run_folder.hpp"

namespace asynevo::pipeline {

/// The estimators 'asynevo run --backend' names: AsynEVO's sliding window, or the incremental baseline
/// (a full-history Ceres smoother standing in for iSAM2, backend::IncrementalEstimator), optionally with
/// the old history held constant ("incremental-frozen", reference/backend.md §8 option B).
enum class BackendKind { kWindow, kIncremental, kIncrementalFrozen };
/// "window", "incremental" or "incremental-frozen"; nullopt otherwise.
std::optional<BackendKind> parseBackendKind(const std::string& name);

/// The estimator of `kind` (AsynEVO's sliding window or an incremental baseline).
std::unique_ptr<backend::Estimator> makeEstimator(BackendKind kind, const backend::EstimatorOptions& options);

struct RunOptions {
  std::string dataset;  ///< ECD-style folder or event file
  std::string format = "auto";
  std::string sensor;            ///< --sensor WxH ("" = from the configuration or the dataset, io/sensor_size.hpp)
  std::string calib;             ///< "" = the dataset's own calibration file
  std::string topic;             ///< --topic: a ROS bag's event topic ("" = its only one)
  std::string rectify_map;       ///< --rectify-map: DSEC's rectification map ("" = rectify_map.h5 beside the
                                 ///< events if any, "none" = raw pixels)
  std::string camera_info_topic;  ///< --camera-info-topic: a ROS bag's CameraInfo topic for the calibration
                                  ///< ("" = the rule of io/dataset.hpp chooseDatasetCalibration)
  std::string gt_topic;          ///< --gt-topic: a ROS bag's pose topic for the ground truth ("" = the rule of
                                 ///< io/dataset.hpp loadDatasetGroundTruth)
  /// --gt-camera-clock: an event_camera_msgs/EventPacket bag's poses (ROS time) are shifted onto its events'
  /// camera clock by the first packet's header stamp minus its first event's time
  /// (docs/reference/formats_rosbag.md#clocks)
  bool gt_camera_clock = false;
  std::string config_path;       ///< "" = defaults (or `config` below)
  std::optional<Config> config;  ///< used instead of config_path when set (the demo)
  BackendKind backend = BackendKind::kWindow;
  std::string out;  ///< run folder
  bool real_time = false;
  double speed = 1.0;  ///< real time: playback rate
  /// Play the event stream this many times back to back (io/repeat_reader.hpp): a long stream from a
  /// short recording, for soak tests. Ground truth is then not written (the camera jumps back at
  /// every seam).
  int repeat = 1;
  /// --skip-ms: the events less than this long after the stream's first event are dropped, as if the
  /// recording had begun later (io/skip_reader.hpp; the evaluation matrix's start offsets).
  double skip_ms = 0;
};

struct RunSummary {
  std::string out_dir;
  std::string dataset_events;  ///< the event file read
  std::string calibration;     ///< the calibration file used, or "BAG (topic NAME)" for a CameraInfo topic
  std::string groundtruth;     ///< where the ground truth came from ("" = none)
  double groundtruth_shift_s = 0;  ///< added to the ground truth's times (--gt-camera-clock)
  std::string format;
  int width = 0, height = 0;
  std::string size_origin;  ///< where width and height came from
  std::string rectify_map;  ///< the rectification map applied to the events ("" = none)
  uint64_t rectified_outside = 0;  ///< events the rectification mapped outside the sensor (dropped)
  uint64_t events_skipped_at_start = 0;  ///< events dropped by --skip-ms
  Config config;  ///< effective configuration
  std::string backend_name;
  PipelineStats pipeline;
  frontend::FrontendStats frontend;
  std::vector<std::pair<int, int>> hot_pixels;  ///< pixels the frontend's hot-pixel filter masked
  backend::EstimatorStats estimator;
  UpdateTimeStats update_time;
  uint64_t knots_written = 0;
  uint64_t landmarks_written = 0;
  uint64_t measurements_written = 0;
  std::optional<uint64_t> groundtruth_poses;  ///< set when stamped_groundtruth.txt was written
  std::vector<std::string> warnings;
  double peak_memory_mb = 0;

  bool initialized() const { return estimator.initialized; }
};

/// Runs a dataset end to end and writes the run folder, also when initialization never succeeded
/// (then the trajectory files are empty; check RunSummary::initialized()). Throws InputError /
/// ConfigError / Error for bad input (missing calibration: before any event is read). `observer`, when
/// given, receives every output the run folder gets, in the same order (the Python bindings keep them in
/// memory).
RunSummary runDataset(const RunOptions& options,
                      const std::function<void(const PipelineProgress&)>& progress = {},
                      PipelineOutput* observer = nullptr);

/// The estimator 'asynevo run --backend' selects, for measurements from `fe` (its binning sets the
/// backend's pixel thresholds) of a camera `camera`.
std::unique_ptr<backend::Estimator> makeEstimator(BackendKind kind, const Config& config,
                                                  const CameraModel& camera, const frontend::Frontend& fe,
                                                  bool real_time);

/// The part of runDataset that processes events: writes config.yaml, builds the frontend and the
/// estimator (options.backend, real_time, speed), runs the pipeline into `writer` (and `observer`, when
/// given) and fills the summary's run fields (backend name, pipeline, frontend and estimator statistics,
/// counts written, noise warnings). `config` holds the reader's sensor size and is valid; `camera` has
/// that size.
void runEvents(EventReader& reader, const CameraModel& camera, const Config& config,
               const RunOptions& options, RunFolderWriter& writer, RunSummary& summary,
               const std::function<void(const PipelineProgress&)>& progress = {},
               PipelineOutput* observer = nullptr);

/// "initialization never succeeded: <estimator's last failure> (… counts …)".
std::string initializationFailureMessage(const RunSummary& summary);

/// A few lines for the terminal: events, features, knots, landmarks, timing, real-time factor.
std::string runSummaryText(const RunSummary& summary);

/// stats.json text of a run.
std::string runStatsJson(const RunSummary& summary, const RunOptions& options);

/// Peak resident memory of this process so far (getrusage), in MiB.
double peakMemoryMb();

}  // namespace asynevo::pipeline
