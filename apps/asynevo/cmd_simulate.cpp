// 'asynevo simulate --scene NAME|FILE --motion PRESET|FILE [--duration S] [--seed N] --out DIR'
// (contract: DESIGN.md §1). The simulator itself is the sim module (docs/simulator.md).
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/sim/scene.hpp"
#include "asynevo/sim/sensor.hpp"
#include "asynevo/sim/simulate.hpp"
#include "commands.hpp"
#include "progress.hpp"

namespace asynevo::cli {

namespace {

struct SimulateOptions {
  sim::SimulationSpec spec;
  std::string out;
  std::string calib;
  int width = 0;  // 0: the sensor preset's
  int height = 0;
  double refractory_us = 100.0;
  double time_jitter_us = 0.0;
  bool no_text = false;
  // Noise options given on the command line: they override the noise level's values.
  CLI::Option* noise_rate = nullptr;
  CLI::Option* noise_on_fraction = nullptr;
  CLI::Option* hot_pixels = nullptr;
  CLI::Option* hot_pixel_rate = nullptr;
  CLI::Option* contrast_sigma = nullptr;
  CLI::Option* contrast_drift = nullptr;
  CLI::Option* time_jitter = nullptr;
};

/// The event model: the noise level's settings, then every noise flag given explicitly.
void resolveSensor(SimulateOptions& options, const CameraModel& camera) {
  sim::SimulationSpec& spec = options.spec;
  const sim::EventSimConfig given = spec.sensor;
  sim::EventSimConfig& c = spec.sensor;
  sim::applyNoiseLevel(spec.noise_level, camera.width(), camera.height(), c);
  if (options.noise_rate->count() > 0) c.noise_rate_hz = given.noise_rate_hz;
  if (options.noise_on_fraction->count() > 0) c.noise_on_fraction = given.noise_on_fraction;
  if (options.hot_pixels->count() > 0) c.hot_pixels = given.hot_pixels;
  if (options.hot_pixel_rate->count() > 0) c.hot_pixel_rate_hz = given.hot_pixel_rate_hz;
  if (options.contrast_sigma->count() > 0) c.contrast_sigma = given.contrast_sigma;
  if (options.contrast_drift->count() > 0) c.contrast_drift = given.contrast_drift;
  if (options.time_jitter->count() > 0) {
    if (!(options.time_jitter_us >= 0) || !std::isfinite(options.time_jitter_us))
      throw std::invalid_argument(
          fmt::format("--time-jitter-us must not be negative, got {}", options.time_jitter_us));
    c.time_jitter_ns = std::llround(options.time_jitter_us * 1e3);
  }
  if (!(options.refractory_us >= 0) || !std::isfinite(options.refractory_us))
    throw std::invalid_argument(fmt::format("--refractory-us must not be negative, got {}", options.refractory_us));
  c.refractory_ns = std::llround(options.refractory_us * 1e3);
}

void runSimulate(SimulateOptions& options) {
  sim::SimulationSpec& spec = options.spec;
  const CameraModel preset = sim::sensorPresetCamera(spec.sensor_preset);  // checks the name first
  if (!options.calib.empty()) {
    spec.camera = readCalibration(options.calib, options.width > 0 ? options.width : preset.width(),
                                  options.height > 0 ? options.height : preset.height());
  }
  if (options.no_text && !spec.write_binary)
    throw std::invalid_argument("--no-text needs --binary: without events.txt the folder must hold events.aevt");
  spec.write_text = !options.no_text;
  const CameraModel camera = sim::specCamera(spec);
  resolveSensor(options, camera);
  Progress progress;
  int64_t first_t_ns = 0;
  const sim::SimulationResult r =
      sim::simulateToFolder(options.spec, options.out, [&](int64_t t_ns, uint64_t events) {
        if (first_t_ns == 0) first_t_ns = t_ns;
        progress.update(events, t_ns, first_t_ns);
      });
  progress.finish();
  const sim::EventSimStats& s = r.stats;
  const double span = durationSeconds(r.begin_ns, r.end_ns);
  fmt::print("scene         {}\n", r.scene_description);
  fmt::print("motion        {}\n", r.motion_description);
  fmt::print("time span     {:.6f} .. {:.6f} s ({:.3f} s)\n", nsToSeconds(r.begin_ns), nsToSeconds(r.end_ns),
             span);
  fmt::print("camera        {}\n", camera.summary());
  fmt::print("events        {} (ON {}, OFF {}, noise {}; {} dropped by the refractory period)\n", s.events,
             s.on_events, s.off_events, s.noise_events, s.refractory_drops);
  if (s.noise_events > 0)
    fmt::print("noise         {} background, {} from {} hot pixels\n", s.background_events, s.hot_pixel_events,
               s.hot_pixels);
  fmt::print("render steps  {} ({:.1f} .. {:.1f} us, max image motion {:.3f} px per step)\n", s.render_steps,
             s.min_step_ns / 1e3, s.max_step_ns / 1e3, s.max_step_motion_px);
  fmt::print("ground truth  {} poses at {} Hz\n", r.groundtruth_poses, options.spec.groundtruth_rate_hz);
  if (r.frames > 0) fmt::print("frames        {}\n", r.frames);
  fmt::print("wall time     {:.2f} s ({:.2f} M events/s, {:.2f} s per simulated s)\n", s.wall_seconds,
             s.wall_seconds > 0 ? static_cast<double>(s.events) / s.wall_seconds * 1e-6 : 0.0,
             span > 0 ? s.wall_seconds / span : 0.0);
  fmt::print("output        {}\n", options.out);
}

}  // namespace

void addSimulateCommand(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  sim::SimulationSpec& spec = options->spec;
  auto* cmd =
      app.add_subcommand("simulate", "Simulate an event camera with exact ground truth (ECD-format folder)");
  // --scene, --motion and --out are required unless --list is given (checked in the callback).
  auto* scene = cmd->add_option(
      "--scene", spec.scene,
      fmt::format("built-in scene ({}) or scene file (YAML)", fmt::join(sim::sceneNames(), ", ")));
  auto* motion = cmd->add_option("--motion", spec.motion,
                                 fmt::format("motion preset ({}) or TUM/ECD ground-truth file",
                                             fmt::join(sim::motionPresetNames(), ", ")));
  cmd->add_option("--duration", spec.duration_s,
                  "seconds to simulate (default: 5 s for a preset, the whole file for a motion file)");
  cmd->add_option("--seed", spec.seed, "random seed (textures, thresholds, noise)")->capture_default_str();
  auto* out = cmd->add_option("--out", options->out, "output folder (ECD layout)");
  auto* list = cmd->add_flag("--list",
                             "print the built-in sensors, noise levels, scenes and motion presets, one "
                             "'kind: name name ...' line each, and exit (for scripts)");
  cmd->add_option("--sensor", spec.sensor_preset,
                  fmt::format("sensor preset: camera model and resolution ({})",
                              fmt::join(sim::sensorPresetNames(), ", ")))
      ->capture_default_str();
  cmd->add_option("--calib", options->calib, "camera: ECD calib.txt or Kalibr YAML (overrides --sensor)");
  cmd->add_option("--width", options->width, "sensor width for an ECD calib.txt (default: the --sensor's)");
  cmd->add_option("--height", options->height, "sensor height for an ECD calib.txt (default: the --sensor's)");
  cmd->add_option("--contrast", spec.sensor.contrast, "mean contrast threshold C (log intensity)")
      ->capture_default_str();
  cmd->add_option("--noise-level", spec.noise_level,
                  fmt::format("all noise settings at once ({}); explicit noise flags override single values",
                              fmt::join(sim::noiseLevelNames(), ", ")))
      ->capture_default_str();
  options->contrast_sigma =
      cmd->add_option("--contrast-sigma", spec.sensor.contrast_sigma, "per-pixel spread of the thresholds")
          ->capture_default_str();
  options->contrast_drift =
      cmd->add_option("--contrast-drift", spec.sensor.contrast_drift,
                      "amplitude D of a slow common-mode threshold drift, C(t) = C_pixel (1 + d(t)), |d| <= D")
          ->capture_default_str();
  options->noise_rate =
      cmd->add_option("--noise-rate", spec.sensor.noise_rate_hz, "background events per pixel per second")
          ->capture_default_str();
  options->noise_on_fraction =
      cmd->add_option("--noise-on-fraction", spec.sensor.noise_on_fraction,
                      "share of ON events among background and hot-pixel events")
          ->capture_default_str();
  options->hot_pixels =
      cmd->add_option("--hot-pixels", spec.sensor.hot_pixels, "number of hot pixels (random positions)")
          ->capture_default_str();
  options->hot_pixel_rate = cmd->add_option("--hot-pixel-rate", spec.sensor.hot_pixel_rate_hz,
                                            "events per second of each hot pixel")
                                ->capture_default_str();
  cmd->add_option("--refractory-us", options->refractory_us, "refractory period (microseconds)")
      ->capture_default_str();
  options->time_jitter = cmd->add_option("--time-jitter-us", options->time_jitter_us,
                                         "sigma of the Gaussian timestamp jitter, truncated at 3 sigma (us)")
                             ->capture_default_str();
  cmd->add_option("--max-step-motion", spec.max_step_motion_px,
                  "largest image motion of a render step in pixels; 0 (default) = 0.3 * max(1, fx / 199.09), "
                  "the DAVIS240C's step angle on every sensor");
  cmd->add_option("--start", spec.start_offset_s,
                  "start this many seconds into the motion (a file: after its first pose; a preset: its motion "
                  "from this phase, starting at its usual first pose)");
  cmd->add_option("--position-scale", spec.motion_file.position_scale,
                  "motion file: multiply positions by this")
      ->capture_default_str();
  cmd->add_option("--smoothing-cutoff", spec.motion_file.cutoff_hz,
                  "low-pass cut-off (Hz) for a motion file, 0 = off")
      ->capture_default_str();
  cmd->add_option("--gt-rate", spec.groundtruth_rate_hz, "ground-truth poses per second")
      ->capture_default_str();
  cmd->add_option("--frame-rate", spec.frame_rate_hz, "also write images/ at this rate (0 = none)")
      ->capture_default_str();
  cmd->add_flag("--binary", spec.write_binary,
                "also write events.aevt (binary; always written for sensors other than 240x180)");
  cmd->add_flag("--no-text", options->no_text, "with --binary: do not write events.txt (saves disk)");
  cmd->add_option("--threads", spec.sensor.threads, "worker threads")->capture_default_str();
  cmd->callback([options, scene, motion, out, list] {
    if (list->count() > 0) {
      fmt::print("sensors: {}\n", fmt::join(sim::sensorPresetNames(), " "));
      fmt::print("noise-levels: {}\n", fmt::join(sim::noiseLevelNames(), " "));
      fmt::print("scenes: {}\n", fmt::join(sim::sceneNames(), " "));
      fmt::print("motions: {}\n", fmt::join(sim::motionPresetNames(), " "));
      return;
    }
    for (const CLI::Option* required : {scene, motion, out})
      if (required->count() == 0) throw CLI::RequiredError(required->get_name());
    try {
      runSimulate(*options);
    } catch (const std::invalid_argument& e) {  // a setting out of range: a user error, not an internal one
      throw Error(std::string("simulate: ") + e.what());
    }
  });
}

}  // namespace asynevo::cli
