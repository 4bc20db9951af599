#include "asynevo/sim/simulate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/event_file.hpp"
#include "asynevo/io/event_text.hpp"
#include "asynevo/io/trajectory_io.hpp"
#include "asynevo/sim/scene.hpp"
#include "asynevo/sim/sensor.hpp"

namespace asynevo::sim {

std::unique_ptr<Motion> makeMotion(const SimulationSpec& spec) {
  if (spec.duration_s < 0 || !std::isfinite(spec.duration_s)) {
    throw std::invalid_argument(fmt::format("duration (--duration) must not be negative, got {}", spec.duration_s));
  }
  if (spec.start_offset_s < 0 || !std::isfinite(spec.start_offset_s)) {
    throw std::invalid_argument(
        fmt::format("start offset (--start) must not be negative, got {}", spec.start_offset_s));
  }
  if (isMotionPreset(spec.motion)) {
    return makePresetMotion(spec.motion, spec.duration_s > 0 ? spec.duration_s : kDefaultPresetDurationS,
                            spec.start_offset_s);
  }
  if (!std::filesystem::exists(spec.motion)) {
    throw InputError(spec.motion,
                     fmt::format("no such motion file (presets: {})", fmt::join(motionPresetNames(), ", ")));
  }
  MotionFileOptions options = spec.motion_file;
  if (spec.duration_s > 0 || spec.start_offset_s > 0) {
    // Window [first pose + offset, ... + duration]: the file's first time is needed first.
    const StampedTrajectory samples = readTumTrajectory(spec.motion);
    if (samples.empty()) throw InputError(spec.motion, "no poses in the file");
    options.begin_ns = std::max(options.begin_ns, samples.front().t_ns + secondsToNs(spec.start_offset_s));
    if (spec.duration_s > 0)
      options.end_ns = std::min(options.end_ns, options.begin_ns + secondsToNs(spec.duration_s));
  }
  return loadMotionFile(spec.motion, options);
}

CameraModel specCamera(const SimulationSpec& spec) {
  return spec.camera ? *spec.camera : sensorPresetCamera(spec.sensor_preset);
}

SimulationResult simulateToFolder(const SimulationSpec& spec, const std::string& out_dir,
                                  const std::function<void(int64_t, uint64_t)>& progress) {
  const CameraModel camera = specCamera(spec);
  if (!spec.write_text && !spec.write_binary) {
    throw std::invalid_argument(
        "--no-text needs --binary: without events.txt the folder must hold events.aevt");
  }
  if (spec.max_step_motion_px < 0 || !std::isfinite(spec.max_step_motion_px)) {
    throw std::invalid_argument(fmt::format(
        "the render step's image motion (--max-step-motion) must be positive, got {}", spec.max_step_motion_px));
  }
  EventSimConfig sensor = spec.sensor;
  sensor.max_pixel_motion = spec.max_step_motion_px > 0 ? spec.max_step_motion_px : defaultMaxStepMotion(camera);
  // The ECD text format and calib.txt imply a 240x180 sensor: other sizes get events.aevt (its header
  // holds the size) and only camchain.yaml (with the resolution), so every reader gets the size right.
  const bool ecd_size = camera.width() == 240 && camera.height() == 180;
  const bool write_binary = spec.write_binary || !ecd_size;
  const std::unique_ptr<Motion> motion = makeMotion(spec);
  Scene scene;
  if (isBuiltinScene(spec.scene)) {
    scene = makeBuiltinScene(spec.scene, *motion, camera, spec.seed);
  } else if (std::filesystem::exists(spec.scene)) {
    scene = loadSceneFile(spec.scene, *motion, camera, spec.seed);
  } else {
    throw InputError(spec.scene,
                     fmt::format("no such scene file (built-in scenes: {})", fmt::join(sceneNames(), ", ")));
  }
  if (!(spec.groundtruth_rate_hz > 0)) throw std::invalid_argument("ground-truth rate must be positive");

  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw Error(fmt::format("{}: cannot create folder: {}", out_dir, ec.message()));
  const std::filesystem::path dir(out_dir);

  SimulationResult result;
  result.scene_description = scene.description;
  result.motion_description = motion->describe();
  result.begin_ns = motion->beginNs();
  result.end_ns = motion->endNs();

  // Calibration.
  // Files of an earlier simulation into the same folder that this one does not write would be read
  // in place of this one's (the loaders pick calib.txt and events.aevt first): remove them.
  std::filesystem::remove(dir / "calib.txt", ec);
  std::filesystem::remove(dir / "events.aevt", ec);
  std::filesystem::remove(dir / "events.txt", ec);
  if (camera.distortionModel() != DistortionModel::kEquidistant && ecd_size)
    writeEcdCalibration((dir / "calib.txt").string(), camera);
  writeKalibrCalibration((dir / "camchain.yaml").string(), camera);

  // Ground truth: the rendered (smoothed) motion, sampled at the requested rate.
  const int64_t gt_dt = std::max<int64_t>(1, secondsToNs(1.0 / spec.groundtruth_rate_hz));
  const StampedTrajectory gt = sampleMotion(*motion, gt_dt);
  writeTumTrajectory(
      (dir / "groundtruth.txt").string(), gt,
      fmt::format("simulated ground truth T_w_c: {}\nt px py pz qx qy qz qw", motion->describe()));
  result.groundtruth_poses = gt.size();

  // Events (and frames).
  std::unique_ptr<EventTextWriter> text;
  if (spec.write_text) text = std::make_unique<EventTextWriter>((dir / "events.txt").string());
  std::unique_ptr<EventFileWriter> binary;
  if (write_binary)
    binary =
        std::make_unique<EventFileWriter>((dir / "events.aevt").string(), camera.width(), camera.height());
  std::ofstream images_txt;
  const int64_t frame_period = spec.frame_rate_hz > 0 ? secondsToNs(1.0 / spec.frame_rate_hz) : 0;
  if (frame_period > 0) {
    std::filesystem::create_directories(dir / "images");
    images_txt.open(dir / "images.txt");
    if (!images_txt)
      throw Error(fmt::format("{}: cannot open file for writing", (dir / "images.txt").string()));
  }
  uint64_t total = 0;
  EventSimulator simulator(camera, scene, sensor, spec.seed);
  const auto sink = [&](const std::vector<Event>& events) {
    if (text)
      for (const Event& e : events) text->write(e);
    if (binary) binary->write(events.data(), events.size());
    total += events.size();
    if (progress) progress(events.back().t_ns, total);
  };
  const auto frame_sink = [&](int64_t t_ns, const std::vector<float>& intensity) {
    cv::Mat image(camera.height(), camera.width(), CV_8U);
    for (int y = 0; y < camera.height(); ++y) {
      for (int x = 0; x < camera.width(); ++x) {
        const float v = intensity[static_cast<std::size_t>(y) * static_cast<std::size_t>(camera.width()) +
                                  static_cast<std::size_t>(x)];
        image.at<uint8_t>(y, x) = static_cast<uint8_t>(std::clamp(std::lround(v * 255.0f), 0L, 255L));
      }
    }
    const std::string name = fmt::format("images/frame_{:08d}.png", result.frames);
    if (!cv::imwrite((dir / name).string(), image))
      throw Error(fmt::format("{}: cannot write image", (dir / name).string()));
    char t[32];
    formatNsAsSeconds(t_ns, t);
    images_txt << t << ' ' << name << '\n';
    ++result.frames;
  };
  result.stats = simulator.run(*motion, motion->beginNs(), motion->endNs(), sink, frame_period,
                               frame_period > 0 ? EventSimulator::FrameSink(frame_sink) : nullptr);
  if (text) text->close();
  if (binary) binary->close();

  // What was simulated.
  std::ofstream meta(dir / "sim.yaml");
  const EventSimConfig& c = sensor;
  const EventSimStats& st = result.stats;
  meta << fmt::format(
      "# asynevo simulate: what produced this folder\n"
      "scene: \"{}\"\nscene_description: \"{}\"\nmotion: \"{}\"\nmotion_description: \"{}\"\nseed: {}\n"
      "start_offset_s: {}\nbegin_s: {:.9f}\nend_s: {:.9f}\nsensor_preset: \"{}\"\ncamera: \"{}\"\n"
      "sensor:\n  contrast: {}\n  contrast_sigma: {}\n  contrast_drift: {}\n  log_epsilon: {}\n"
      "  refractory_us: {}\n  max_pixel_motion: {}\n"
      "noise:\n  level: \"{}\"\n  background_rate_hz: {}\n  on_fraction: {}\n  hot_pixels: {}\n"
      "  hot_pixel_rate_hz: {}\n  time_jitter_us: {}\n"
      "groundtruth_rate_hz: {}\nframe_rate_hz: {}\n"
      "files:\n  events_txt: {}\n  events_aevt: {}\n"
      "stats:\n  events: {}\n  on_events: {}\n  off_events: {}\n  noise_events: {}\n  background_events: {}\n"
      "  hot_pixel_events: {}\n  refractory_drops: {}\n"
      "  render_steps: {}\n  min_step_us: {:.3f}\n  max_step_us: {:.3f}\n  max_step_motion_px: {:.4f}\n",
      spec.scene, scene.description, spec.motion, motion->describe(), spec.seed, spec.start_offset_s,
      nsToSeconds(result.begin_ns), nsToSeconds(result.end_ns), spec.camera ? "custom" : spec.sensor_preset,
      camera.summary(), c.contrast, c.contrast_sigma, c.contrast_drift, c.log_epsilon, c.refractory_ns / 1e3,
      c.max_pixel_motion, spec.noise_level, c.noise_rate_hz, c.noise_on_fraction, st.hot_pixels,
      c.hot_pixel_rate_hz, static_cast<double>(c.time_jitter_ns) / 1e3, spec.groundtruth_rate_hz,
      spec.frame_rate_hz, spec.write_text, write_binary, st.events, st.on_events, st.off_events, st.noise_events,
      st.background_events, st.hot_pixel_events, st.refractory_drops, st.render_steps, st.min_step_ns / 1e3,
      st.max_step_ns / 1e3, st.max_step_motion_px);
  if (!meta) throw Error(fmt::format("{}: write failed", (dir / "sim.yaml").string()));
  return result;
}

}  // namespace asynevo::sim
