#pragma once
// Camera motion for the simulator: T_w_c(t), camera-to-world, defined for t in [beginNs(), endNs()].
//
//   * Built-in presets (analytic, smooth): static, rotation, translation, 6dof, fast-translation, speed-ramp,
//     slow-start. The world frame is fixed (camera looking along +z, x right, y down at the identity);
//     the first pose is the preset's pose at phase 0, also with a start offset (the identity for static
//     fast-translation and speed-ramp; rotation, translation, 6dof and slow-start start a little rotated/shifted).
//   * A ground-truth file (TUM or ECD groundtruth.txt): resampled, low-pass filtered (mocap poses are
//     noisy at the millisecond scale, DESIGN.md §5) and represented by a uniform cumulative cubic
//     B-spline on R³ and SO(3), so pose, velocity and acceleration are continuous.
// Formulas and choices: docs/simulator.md §Motion.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "asynevo/core/stamped_pose.hpp"

namespace asynevo::sim {

class Motion {
 public:
  virtual ~Motion() = default;
  virtual int64_t beginNs() const = 0;
  virtual int64_t endNs() const = 0;
  /// T_w_c at t_ns; t is clamped to [beginNs(), endNs()].
  virtual StampedPose pose(int64_t t_ns) const = 0;
  /// A short description for logs and the output folder's sim.yaml.
  virtual std::string describe() const = 0;
};

/// A motion given by a function of time (seconds since begin).
class AnalyticMotion : public Motion {
 public:
  using Function = std::function<void(double t_s, Eigen::Vector3d& p_w_c, Eigen::Quaterniond& q_w_c)>;
  AnalyticMotion(std::string description, int64_t begin_ns, int64_t end_ns, Function function);
  int64_t beginNs() const override { return begin_ns_; }
  int64_t endNs() const override { return end_ns_; }
  StampedPose pose(int64_t t_ns) const override;
  std::string describe() const override { return description_; }

 private:
  std::string description_;
  int64_t begin_ns_;
  int64_t end_ns_;
  Function function_;
};

/// Names of the built-in motion presets.
std::vector<std::string> motionPresetNames();
/// True when `name` is a preset.
bool isMotionPreset(const std::string& name);
/// A preset motion over [0, duration_s]. With `start_s` > 0 the preset's motion from start_s to
/// start_s + duration_s, re-based so that its first pose is the preset's pose at phase 0:
/// T(t) = T_f(0) T_f(S)⁻¹ T_f(t + S). Throws std::invalid_argument for an unknown name or a negative start.
std::unique_ptr<Motion> makePresetMotion(const std::string& name, double duration_s, double start_s = 0.0);

struct MotionFileOptions {
  double cutoff_hz = 15.0;       ///< Gaussian low-pass cut-off (-3 dB); 0 disables the smoothing
  double sample_dt_s = 0.005;    ///< spacing of the resampled poses = B-spline knot spacing
  double position_scale = 1.0;   ///< multiplies positions (e.g. to shrink a trajectory)
  int64_t begin_ns = INT64_MIN;  ///< optional time window (file time base)
  int64_t end_ns = INT64_MAX;
};

/// Uniform cumulative cubic B-spline on R³ × SO(3) (Kim, Kim & Shin, SIGGRAPH 1995; Lovegrove,
/// Patron-Perez & Sibley, BMVC 2013; Sommer et al., CVPR 2020):
///   p(u) = c_i + Σ_{j=1..3} B̃_j(u) (c_{i+j} − c_{i+j−1})
///   R(u) = R_i Π_{j=1..3} Exp(B̃_j(u) Log(R_{i+j−1}ᵀ R_{i+j}))
/// with B̃_1 = (5 + 3u − 3u² + u³)/6, B̃_2 = (1 + 3u + 3u² − 2u³)/6, B̃_3 = u³/6.
class SplineMotion : public Motion {
 public:
  /// Smooths and fits `samples` (time-ordered poses, at least two). Throws std::invalid_argument when
  /// fewer than two samples fall in the window.
  SplineMotion(const StampedTrajectory& samples, const MotionFileOptions& options, std::string description);
  int64_t beginNs() const override { return begin_ns_; }
  int64_t endNs() const override { return end_ns_; }
  StampedPose pose(int64_t t_ns) const override;
  std::string describe() const override { return description_; }

 private:
  std::string description_;
  int64_t begin_ns_ = 0;
  int64_t end_ns_ = 0;
  int64_t knot_dt_ns_ = 0;
  int64_t grid_origin_ns_ = 0;                    // τ_0, time of the first resampled pose
  std::vector<Eigen::Vector3d> positions_;        // control points c_0 .. c_{n+1}
  std::vector<Eigen::Quaterniond> rotations_;     // control rotations R_0 .. R_{n+1}
  std::vector<Eigen::Vector3d> rotation_deltas_;  // Log(R_kᵀ R_{k+1})
};

/// Reads a TUM / ECD ground-truth file and builds the smoothed spline motion. Errors in the file
/// throw InputError (file and line).
std::unique_ptr<Motion> loadMotionFile(const std::string& path, const MotionFileOptions& options = {});

/// Samples `motion` every `dt_ns` from beginNs() to endNs() (both included).
StampedTrajectory sampleMotion(const Motion& motion, int64_t dt_ns);

}  // namespace asynevo::sim
