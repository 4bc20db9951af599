#include "asynevo/backend/factors/fixed_pose_projection_factor.hpp"

#include "asynevo/backend/factors/projection_residual.hpp"

namespace asynevo::backend {

FixedPoseProjectionFactor::FixedPoseProjectionFactor(const lie::SE3& T_w_c, const Eigen::Vector2d& z, double sigma,
                                                     double min_depth)
    : R_cw_(T_w_c.rotation().transpose()),
      t_cw_(-(R_cw_ * T_w_c.translation())),
      z_(z),
      inv_sigma_(1.0 / sigma),
      min_depth_(min_depth) {}

bool FixedPoseProjectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                         double** jacobians) const {
  const Eigen::Map<const Eigen::Vector3d> p_w(parameters[0]);
  const Eigen::Vector3d p_c = R_cw_ * p_w + t_cw_;
  const bool jacobian = jacobians != nullptr && jacobians[0] != nullptr;
  Eigen::Matrix<double, 2, 3> d_r_d_pc;
  if (!projectionResidual(p_c, z_, inv_sigma_, min_depth_, residuals, jacobian ? &d_r_d_pc : nullptr))
    return false;  // cheirality (also rejects NaN)
  if (jacobian) Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>{jacobians[0]} = d_r_d_pc * R_cw_;
  return true;
}

}  // namespace asynevo::backend
