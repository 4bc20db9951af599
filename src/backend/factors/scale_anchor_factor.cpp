#include "asynevo/backend/factors/scale_anchor_factor.hpp"

#include <array>

#include "asynevo/backend/factors/pose_block.hpp"

namespace asynevo::backend {

bool ScaleAnchorFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const lie::SE3 T_a = poseFromBlock(parameters[0]);
  const lie::SE3 T_b = poseFromBlock(parameters[1]);
  const Eigen::Vector3d d = T_b.translation() - T_a.translation();
  const double norm = d.norm();
  if (!(norm > 1e-12)) return false;  // direction undefined: reject the step
  residuals[0] = (norm - distance_) * inv_sigma_;
  if (jacobians == nullptr) return true;
  const Eigen::Vector3d u = d / norm;
  const std::array<const lie::SE3*, 2> poses = {&T_a, &T_b};
  for (int i = 0; i < 2; ++i) {
    if (jacobians[i] == nullptr) continue;
    Eigen::Map<Eigen::Matrix<double, 1, 7>> J(jacobians[i]);
    J.setZero();
    J.head<3>() = (i == 0 ? -inv_sigma_ : inv_sigma_) * u.transpose() * poses[static_cast<std::size_t>(i)]->rotation();
  }
  return true;
}

}  // namespace asynevo::backend
