#pragma once
// Parameter-block layout of the backend's Ceres problems (docs/math/gp_backend.md §5):
//
//   pose      7 doubles  [t_x, t_y, t_z, q_x, q_y, q_z, q_w]   T_w_c (camera-to-world); the same order
//                                                              as a TUM trajectory line after the time
//   velocity  6 doubles  ϖ = [v; ω], body-frame twist (Ṫ = Tϖ^), Euclidean
//   landmark  3 doubles  p_w, world xyz, Euclidean
//
// Pose blocks use SE3Manifold (Plus = T·Exp(δ), δ = [ρ; φ]) with the tangent-Jacobian convention: every
// cost function writes its 6-column tangent Jacobian into the first 6 columns of the 7-column ambient
// Jacobian and zeros the last column; SE3Manifold::PlusJacobian returns [I₆; 0₁ₓ₆], so Ceres, which only
// ever uses J_ambient·PlusJacobian, sees the true tangent Jacobian (reference/backend.md §6).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

constexpr int kPoseSize = 7;
constexpr int kPoseTangentSize = 6;
constexpr int kVelocitySize = 6;
constexpr int kLandmarkSize = 3;

/// Reads a pose block (the quaternion is normalized on the way).
inline lie::SE3 poseFromBlock(const double* x) {
  const Eigen::Map<const Eigen::Quaterniond> q(x + 3);
  return lie::SE3(q, Eigen::Vector3d(x[0], x[1], x[2]));
}

/// Writes a pose block (unit quaternion with q_w ≥ 0).
inline void poseToBlock(const lie::SE3& T, double* x) {
  Eigen::Quaterniond q = T.quaternion();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  x[0] = T.translation().x();
  x[1] = T.translation().y();
  x[2] = T.translation().z();
  x[3] = q.x();
  x[4] = q.y();
  x[5] = q.z();
  x[6] = q.w();
}

/// Row-major view of the ambient Jacobian Ceres hands to a cost function for a pose block.
template <int Rows>
using PoseJacobianMap = Eigen::Map<Eigen::Matrix<double, Rows, kPoseSize, Eigen::RowMajor>>;

/// Writes a tangent Jacobian (Rows×6) into a pose block's ambient Jacobian (Rows×7, last column 0).
template <int Rows, typename Derived>
inline void setPoseJacobian(double* jacobian, const Eigen::MatrixBase<Derived>& tangent) {
  PoseJacobianMap<Rows> J(jacobian);
  J.template leftCols<kPoseTangentSize>() = tangent;
  J.col(kPoseTangentSize).setZero();
}

}  // namespace asynevo::backend
