// 'asynevo simulate --scene NAME|FILE --motion PRESET|FILE [--duration S] [--seed N] --out DIR'
// (contract: DESIGN.md §1). The simulator itself is the sim module (docs/simulator.md).
#include <fmt/format.h>

#include <stdexcept>
#include <string>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/sim/scene.hpp"
#include "asynevo/sim/simulate.hpp"
#include "commands.hpp"
#include "progress.hpp"

namespace asynevo::cli {

namespace {

struct SimulateOptions {
  sim::SimulationSpec spec;
  std::string out;
  std::string calib;
  int width = 240;
  int height = 180;
};

void runSimulate(SimulateOptions& options) {
  if (!options.calib.empty())
    options.spec.camera = readCalibration(options.calib, options.width, options.height);
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
  fmt::print("events        {} (ON {}, OFF {}, noise {}; {} dropped by the refractory period)\n", s.events,
             s.on_events, s.off_events, s.noise_events, s.refractory_drops);
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
  cmd->add_option("--scene", spec.scene,
                  fmt::format("built-in scene ({}) or scene file (YAML)", fmt::join(sim::sceneNames(), ", ")))
      ->required();
  cmd->add_option("--motion", spec.motion,
                  fmt::format("motion preset ({}) or TUM/ECD ground-truth file",
                              fmt::join(sim::motionPresetNames(), ", ")))
      ->required();
  cmd->add_option("--duration", spec.duration_s,
                  "seconds to simulate (default: 5 s for a preset, the whole file for a motion file)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", spec.seed, "random seed (textures, thresholds, noise)")->capture_default_str();
  cmd->add_option("--out", options->out, "output folder (ECD layout)")->required();
  cmd->add_option("--calib", options->calib, "camera: ECD calib.txt or Kalibr YAML (default: ECD DAVIS240C)");
  cmd->add_option("--width", options->width, "sensor width for an ECD calib.txt")->capture_default_str();
  cmd->add_option("--height", options->height, "sensor height for an ECD calib.txt")->capture_default_str();
  cmd->add_option("--contrast", spec.sensor.contrast, "mean contrast threshold C (log intensity)")
      ->capture_default_str();
  cmd->add_option("--contrast-sigma", spec.sensor.contrast_sigma, "per-pixel spread of the thresholds")
      ->capture_default_str();
  cmd->add_option("--noise-rate", spec.sensor.noise_rate_hz, "background noise events per pixel per second")
      ->capture_default_str();
  cmd->add_option("--hot-pixels", spec.sensor.hot_pixels, "number of hot pixels (random, 50 Hz each)")
      ->capture_default_str();
  cmd->add_option("--start", spec.start_offset_s, "motion file: start this many seconds after its first pose")
      ->check(CLI::NonNegativeNumber);
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
  cmd->add_flag("--binary", spec.write_binary, "also write events.aevt (binary)");
  cmd->add_option("--threads", spec.sensor.threads, "worker threads")->capture_default_str();
  cmd->callback([options] {
    try {
      runSimulate(*options);
    } catch (const std::invalid_argument& e) {  // a setting out of range: a user error, not an internal one
      throw Error(std::string("simulate: ") + e.what());
    }
  });
}

}  // namespace asynevo::cli
