#pragma once
// Synthetic trajectories for the evaluation tests.

#include <Eigen/Geometry>
#include <cmath>

#include "asynevo/core/stamped_pose.hpp"

namespace asynevo::eval::test {

/// A helix with a wobbling orientation, `n` poses every `dt_ns`.
inline StampedTrajectory helix(std::size_t n = 1000, int64_t dt_ns = 10'000'000, int64_t t0_ns = 0) {
  StampedTrajectory traj;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 1e-9 * static_cast<double>(dt_ns) * static_cast<double>(i);
    StampedPose pose;
    pose.t_ns = t0_ns + dt_ns * static_cast<int64_t>(i);
    pose.p_w_c = Eigen::Vector3d(std::cos(t), std::sin(t), 0.1 * t);
    pose.q_w_c = Eigen::Quaterniond(Eigen::AngleAxisd(t, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(0.2 * std::sin(3 * t), Eigen::Vector3d::UnitX()));
    traj.push_back(pose);
  }
  return traj;
}

/// Applies p ↦ s R p + t, q ↦ R q (a similarity of the world frame) to every pose.
inline StampedTrajectory transformed(const StampedTrajectory& in, double s, const Eigen::Quaterniond& R,
                                     const Eigen::Vector3d& t) {
  StampedTrajectory out = in;
  for (auto& pose : out) {
    pose.p_w_c = s * (R * pose.p_w_c) + t;
    pose.q_w_c = R * pose.q_w_c;
  }
  return out;
}

/// Straight line along x at `speed` m/s with identity orientation.
inline StampedTrajectory line(std::size_t n, int64_t dt_ns, double speed) {
  StampedTrajectory traj;
  for (std::size_t i = 0; i < n; ++i) {
    StampedPose pose;
    pose.t_ns = dt_ns * static_cast<int64_t>(i);
    pose.p_w_c = Eigen::Vector3d(speed * 1e-9 * static_cast<double>(pose.t_ns), 0, 0);
    traj.push_back(pose);
  }
  return traj;
}

}  // namespace asynevo::eval::test
