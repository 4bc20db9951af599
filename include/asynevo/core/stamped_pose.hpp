#pragma once
// Time-stamped poses and twists: what trajectory files hold (TUM / ECD ground truth, velocities.txt)
// and what the evaluator compares. Poses are T_w_c, camera-to-world (DESIGN.md §3).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace asynevo {

/// One pose T_w_c at time t_ns: p_w = q_w_c * p_c + p_w_c.
struct StampedPose {
  int64_t t_ns = 0;
  Eigen::Vector3d p_w_c = Eigen::Vector3d::Zero();            ///< camera position in the world
  Eigen::Quaterniond q_w_c = Eigen::Quaterniond::Identity();  ///< camera-to-world rotation (unit)
};

/// A pose sequence ordered by time (non-decreasing t_ns). Named StampedTrajectory so it does not
/// clash with the backend's knot Trajectory.
using StampedTrajectory = std::vector<StampedPose>;

/// Body-frame twist at time t_ns (the camera frame is the body frame): linear velocity v [m/s] and
/// angular velocity w [rad/s], as in a run folder's velocities.txt.
struct StampedTwist {
  int64_t t_ns = 0;
  Eigen::Vector3d v_c = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_c = Eigen::Vector3d::Zero();
};

}  // namespace asynevo
