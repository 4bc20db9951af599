#pragma once
// Trajectory files.
//
//   TUM / rpg_trajectory_evaluation / ECD groundtruth.txt:  t tx ty tz qx qy qz qw
//   velocities.txt (run folder):                            t vx vy vz wx wy wz
//
// One record per line, fields separated by spaces or tabs, time in seconds (parsed exactly to int64
// ns), Hamilton quaternion with w last. Blank lines and lines starting with '#' are skipped. Every
// problem throws InputError naming the file and line: a missing or empty file, a wrong field count,
// a non-numeric or non-finite value, a zero quaternion, a time going backwards. A quaternion whose
// norm is not 1 is normalized and counted (TrajectoryReadReport), not rejected.

#include <cstdint>
#include <string>
#include <vector>

#include "asynevo/core/stamped_pose.hpp"

namespace asynevo {

/// What a reader noticed besides the data.
struct TrajectoryReadReport {
  uint64_t records = 0;                    ///< poses (or twists) read
  uint64_t skipped_lines = 0;              ///< blank and comment lines
  uint64_t normalized_quaternions = 0;     ///< quaternions whose |norm - 1| exceeded kQuaternionNormTolerance
  uint64_t first_normalized_line = 0;      ///< line of the first such quaternion (0 = none)
  double max_quaternion_norm_error = 0.0;  ///< largest |norm - 1| seen
};

/// |‖q‖ - 1| above this counts as a non-unit quaternion (normalized, with a warning). Files printed
/// with 6 decimals stay below it.
constexpr double kQuaternionNormTolerance = 1e-4;

/// Reads a TUM-format trajectory (also rpg_trajectory_evaluation's stamped_*.txt).
StampedTrajectory readTumTrajectory(const std::string& path, TrajectoryReadReport* report = nullptr);

/// Reads an ECD groundtruth.txt (same layout as TUM).
StampedTrajectory readEcdGroundTruth(const std::string& path, TrajectoryReadReport* report = nullptr);

/// Writes TUM format: time with 9 decimals (exact ns), other values in shortest round-trip form.
/// `header` (optional) is written as '#' comment lines first. Throws Error when the file cannot be
/// written.
void writeTumTrajectory(const std::string& path, const StampedTrajectory& trajectory,
                        const std::string& header = "");

/// Reads a velocities.txt: t vx vy vz wx wy wz (body-frame twist).
std::vector<StampedTwist> readVelocities(const std::string& path, TrajectoryReadReport* report = nullptr);

/// Writes a velocities.txt.
void writeVelocities(const std::string& path, const std::vector<StampedTwist>& twists,
                     const std::string& header = "");

}  // namespace asynevo
