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

/// The exact body-frame twist of helix() at t_ns: v = Rᵀ ṗ with ṗ = (−sin t, cos t, 0.1); with
/// R = Rz(t) Rx(b), b = 0.2 sin 3t: ω = Rx(b)ᵀ e_z + ḃ e_x, ḃ = 0.6 cos 3t.
inline StampedTwist helixTwist(int64_t t_ns) {
  const double t = 1e-9 * static_cast<double>(t_ns);
  const Eigen::Matrix3d Rx =
      Eigen::AngleAxisd(0.2 * std::sin(3 * t), Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(t, Eigen::Vector3d::UnitZ()).toRotationMatrix() * Rx;
  StampedTwist twist;
  twist.t_ns = t_ns;
  twist.v_c = R.transpose() * Eigen::Vector3d(-std::sin(t), std::cos(t), 0.1);
  twist.w_c = Rx.transpose() * Eigen::Vector3d::UnitZ() + 0.6 * std::cos(3 * t) * Eigen::Vector3d::UnitX();
  return twist;
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
