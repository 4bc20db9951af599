#pragma once
// One call from a scene name/file and a motion preset/file to an ECD-format folder:
//
//   events.txt        t x y p          (seconds with 9 decimals, p 1 = ON, 0 = OFF), time-ordered
//   groundtruth.txt   t px py pz qx qy qz qw   (T_w_c of the rendered motion, `groundtruth_rate_hz`)
//   calib.txt         fx fy cx cy k1 k2 p1 p2 k3   (only radtan/pinhole cameras of 240x180 pixels, the
//                     size an ECD calib.txt implies)
//   camchain.yaml     the camera as a Kalibr camchain (with the resolution), always
//   sim.yaml          what was simulated: scene, motion, seed, sensor and noise settings, statistics
//   images/ + images.txt   optional frames (PNG, linear intensity) at `frame_rate_hz`
//   events.aevt       binary copy of the events (AsynEVO's .aevt format, with the sensor size): with
//                     `write_binary`, and always for sensors other than 240x180, whose size the ECD text
//                     format cannot tell the readers

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/sim/event_simulator.hpp"
#include "asynevo/sim/motion.hpp"

namespace asynevo::sim {

constexpr double kDefaultPresetDurationS = 5.0;

struct SimulationSpec {
  std::string scene = "shapes";  ///< built-in scene name or scene file (YAML)
  std::string motion = "6dof";   ///< motion preset or TUM/ECD ground-truth file
  double duration_s = 0;         ///< 0 = preset default (5 s) or the whole span of a motion file
  /// Motion files: start this long after the file's first pose. Presets: the preset's motion from this
  /// phase on, re-based to its phase-0 first pose (makePresetMotion).
  double start_offset_s = 0;
  uint64_t seed = 1;
  std::string sensor_preset = "davis240c";  ///< camera when `camera` is not set (sensorPresetNames())
  std::optional<CameraModel> camera;        ///< overrides the preset (e.g. a calibration file)
  /// The event model. Its max_pixel_motion is replaced by `max_step_motion_px` (below).
  EventSimConfig sensor;
  /// Recorded in sim.yaml only: the noise level the caller applied to `sensor` (applyNoiseLevel).
  std::string noise_level = "none";
  /// Image-motion bound of a render step (pixels); 0 = defaultMaxStepMotion(camera).
  double max_step_motion_px = 0;
  MotionFileOptions motion_file;  ///< smoothing of motion files
  double groundtruth_rate_hz = 1000.0;
  double frame_rate_hz = 0;   ///< > 0: also write images/ and images.txt
  bool write_binary = false;  ///< also write events.aevt
  bool write_text = true;     ///< write events.txt (false needs write_binary)
};

/// The camera a spec simulates: `camera` when set, else the sensor preset's.
CameraModel specCamera(const SimulationSpec& spec);

struct SimulationResult {
  EventSimStats stats;
  std::string scene_description;
  std::string motion_description;
  int64_t begin_ns = 0;
  int64_t end_ns = 0;
  uint64_t groundtruth_poses = 0;
  uint64_t frames = 0;
};

/// Builds the motion of a spec (preset or file, windowed by duration).
std::unique_ptr<Motion> makeMotion(const SimulationSpec& spec);

/// Simulates and writes the folder `out_dir` (created if needed). `progress` (optional) is called
/// after each render step with the simulated time reached. Throws InputError for bad input files,
/// std::invalid_argument for bad settings, Error when the output cannot be written.
SimulationResult simulateToFolder(
    const SimulationSpec& spec, const std::string& out_dir,
    const std::function<void(int64_t t_ns, uint64_t events)>& progress = nullptr);

}  // namespace asynevo::sim
