#pragma once
// One call from a scene name/file and a motion preset/file to an ECD-format folder:
//
//   events.txt        t x y p          (seconds with 9 decimals, p 1 = ON, 0 = OFF), time-ordered
//   groundtruth.txt   t px py pz qx qy qz qw   (T_w_c of the rendered motion, `groundtruth_rate_hz`)
//   calib.txt         fx fy cx cy k1 k2 p1 p2 k3   (radtan/pinhole cameras; camchain.yaml for others)
//   camchain.yaml     the same camera as a Kalibr camchain (with the resolution)
//   sim.yaml          what was simulated: scene, motion, seed, sensor settings, statistics
//   images/ + images.txt   optional frames (PNG, linear intensity) at `frame_rate_hz`
//   events.aevt       optional binary copy of the events (AsynEVO's .aevt format)

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
  double start_offset_s = 0;     ///< motion files: start this long after the file's first pose
  uint64_t seed = 1;
  std::optional<CameraModel> camera;  ///< default: the ECD DAVIS240C calibration (radtan, 240x180)
  EventSimConfig sensor;
  MotionFileOptions motion_file;  ///< smoothing of motion files
  double groundtruth_rate_hz = 1000.0;
  double frame_rate_hz = 0;   ///< > 0: also write images/ and images.txt
  bool write_binary = false;  ///< also write events.aevt
};

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
