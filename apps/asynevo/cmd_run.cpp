// 'asynevo run --dataset PATH|--frames DIR [--format auto|ecd|mvsec|aevt|evt3|evt2|dat|aedat4|rosbag|dsec] [--calib FILE] [--config FILE]
//  [--backend window|incremental|incremental-frozen] [--realtime [--speed X]] --out DIR' (contract: DESIGN.md §1).
// The work is pipeline::runDataset (docs/pipeline.md), or with --frames the frame-based baseline
// pipeline::runFrameFolder (docs/results/repeated_texture.md); this file parses, shows progress and reports.
#include <fmt/format.h>

#include <string>

#include "allocator.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/pipeline/run.hpp"
#include "asynevo/pipeline/run_frames.hpp"
#include "commands.hpp"
#include "progress.hpp"
#include "sensor_option.hpp"

namespace asynevo::cli {

namespace {

struct RunCliOptions {
  pipeline::RunOptions run;
  std::string backend = "window";
  std::string frames;  ///< --frames DIR: the frame-based (KLT) baseline instead of the events
  frames::KltOptions klt;
};

void runRun(RunCliOptions& options) {
  const auto kind = pipeline::parseBackendKind(options.backend);
  if (!kind) throw Error("unknown backend '" + options.backend + "' (window, incremental, incremental-frozen)");
  options.run.backend = *kind;
  if (options.run.dataset.empty() == options.frames.empty())
    throw Error("give exactly one of --dataset PATH (events) and --frames DIR (intensity frames)");
  if (!options.frames.empty()) {
    if (options.run.skip_ms > 0) throw Error("--skip-ms applies to an event stream (--dataset), not to --frames");
    pipeline::FramesRunOptions frames;
    frames.frames = options.frames;
    frames.calib = options.run.calib;
    frames.config_path = options.run.config_path;
    frames.backend = *kind;
    frames.out = options.run.out;
    frames.klt = options.klt;
    const pipeline::RunSummary summary = pipeline::runFrameFolder(frames);
    // runSummaryText's first two lines count events and the event frontend's features: replaced here.
    std::string text = pipeline::runSummaryText(summary);
    text = text.substr(text.find('\n', text.find('\n') + 1) + 1);
    const auto& p = summary.pipeline;
    fmt::print("frames          {} over {:.3f} s ({}x{}, KLT baseline, {} pyramid levels), {:.2f} s wall time\n"
               "KLT tracks      {} features, {} measurements, at most {} at once\n{}",
               p.packets, nsToSeconds(p.last_t_ns - p.first_t_ns), summary.width, summary.height,
               options.klt.pyramid_levels, p.wall_seconds, summary.frontend.features_created, p.measurements,
               summary.frontend.max_active_features, text);
    if (!summary.initialized())
      throw Error(pipeline::initializationFailureMessage(summary) + "\n  partial outputs are in " + summary.out_dir);
    return;
  }
  useOneAllocatorArena();  // before the run's threads: flat memory over long runs
  Progress progress;
  pipeline::RunSummary summary;
  summary = pipeline::runDataset(options.run, [&](const pipeline::PipelineProgress& p) {
    progress.update(p.events, p.event_t_ns, p.first_t_ns, p.lag_ns);
  });
  progress.finish();
  fmt::print("{}", pipeline::runSummaryText(summary));
  if (!summary.initialized())
    throw Error(pipeline::initializationFailureMessage(summary) +
                "\n  partial outputs (tracks.txt, stats.json, config.yaml) are in " + summary.out_dir);
}

}  // namespace

void addRunCommand(CLI::App& app) {
  static RunCliOptions options;  // CLI11 binds options to stable addresses; one parse per process
  pipeline::RunOptions& run = options.run;
  auto* cmd = app.add_subcommand("run", "Estimate the camera trajectory of a dataset");
  cmd->add_option("--dataset", run.dataset, "ECD-style folder or event file (or --frames)");
  cmd->add_option("--frames", options.frames,
                  "instead of events: a folder of intensity frames (images.txt, as 'simulate --frame-rate' "
                  "writes) run by the frame-based KLT baseline into the same backend");
  cmd->add_option("--klt-levels", options.klt.pyramid_levels,
                  "with --frames: Lucas-Kanade pyramid levels above the image (OpenCV maxLevel)")
      ->check(CLI::Range(0, 6))
      ->capture_default_str();
  cmd->add_flag("--klt-predict", options.klt.predict,
                "with --frames: start each Lucas-Kanade search at a constant-velocity prediction");
  cmd->add_option("--klt-features", options.klt.max_features, "with --frames: features tracked at once")
      ->check(CLI::Range(10, 2000))
      ->capture_default_str();
  cmd->add_option("--format", run.format, "input format (auto, ecd, mvsec, aevt, evt3, evt2, dat, aedat4, rosbag, dsec)")->capture_default_str();
  cmd->add_option("--calib", run.calib,
                  "calibration file (ECD calib.txt or Kalibr YAML; default: the dataset's, else a ROS bag's "
                  "sensor_msgs/CameraInfo topic)");
  cmd->add_option("--config", run.config_path, "configuration YAML (overrides the defaults; see config/)");
  addSensorOption(cmd, run.sensor);
  addTopicOption(cmd, run.topic);
  addRectifyMapOption(cmd, run.rectify_map);
  addCameraInfoTopicOption(cmd, run.camera_info_topic);
  addGtTopicOption(cmd, run.gt_topic);
  cmd->add_flag("--gt-camera-clock", run.gt_camera_clock,
                "ROS bag of event_camera_msgs/EventPacket: shift the bag's poses (ROS time) onto the events' "
                "camera clock by the first packet's header stamp minus its first event's time (good to the "
                "driver's latency)");
  cmd->add_option("--backend", options.backend,
                  "estimator: window (AsynEVO), incremental (full-history smoother baseline) or "
                  "incremental-frozen (the same with old knots held constant)")
      ->check(CLI::IsMember({"window", "incremental", "incremental-frozen"}))
      ->capture_default_str();
  cmd->add_option("--out", run.out, "run folder to write")->required();
  cmd->add_flag("--realtime", run.real_time,
                "pace events by their timestamps against the wall clock, cap the solver time and report the "
                "backend lag (not deterministic)");
  cmd->add_option("--speed", run.speed, "with --realtime: playback rate (2 = twice real time)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--repeat", run.repeat,
                  "play the event stream this many times back to back (soak tests; ground truth is then not "
                  "written)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--skip-ms", run.skip_ms,
                  "leave out the events less than this long after the stream's first event, as if the recording "
                  "had begun later (the evaluation matrix's start offsets)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->callback([] { runRun(options); });
}

}  // namespace asynevo::cli
