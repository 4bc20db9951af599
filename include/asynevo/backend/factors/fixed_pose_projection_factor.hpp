#pragma once
// Projection of a landmark into a camera pose held fixed: the measurements of a still-active landmark
// made at times whose knots the window has already marginalized (forced marginalization, N_max).
//
//   p_c = R_cw p_w + t_cw,  r = (π(p_c) − z)/σ,  ∂r/∂p_w = (1/σ) Jπ R_cw,
//   Jπ = [1/z 0 −x/z²; 0 1/z −y/z²]            (reference/backend.md §4, the pose part held constant)
//
// The pose is the GP-interpolated estimate at the measurement time when its knots left the window. This
// conditions on that estimate instead of marginalizing it (as local bundle adjustment does with fixed
// keyframes, Mur-Artal et al., ORB-SLAM, T-RO 2015, §VI-B): slightly over-confident, but the landmark
// keeps its old views, so its depth, and with it the map scale, survives the knots that saw it.
// Evaluate returns false when the point is not in front of the camera.

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

class FixedPoseProjectionFactor final : public ceres::SizedCostFunction<2, 3> {
 public:
  /// `T_w_c` camera-to-world pose; `z` normalized image point; `sigma` in normalized units.
  FixedPoseProjectionFactor(const lie::SE3& T_w_c, const Eigen::Vector2d& z, double sigma, double min_depth = 1e-6);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Eigen::Matrix3d R_cw_;
  Eigen::Vector3d t_cw_;
  Eigen::Vector2d z_;
  double inv_sigma_;
  double min_depth_;
};

}  // namespace asynevo::backend
