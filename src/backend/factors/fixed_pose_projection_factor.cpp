#include "asynevo/backend/factors/fixed_pose_projection_factor.hpp"

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
  if (!(p_c.z() > min_depth_)) return false;  // cheirality (also rejects NaN)
  const double inv_z = 1.0 / p_c.z();
  const double u = p_c.x() * inv_z;
  const double v = p_c.y() * inv_z;
  residuals[0] = (u - z_.x()) * inv_sigma_;
  residuals[1] = (v - z_.y()) * inv_sigma_;
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Matrix<double, 2, 3> d_r_d_pc;
    const double s = inv_sigma_ * inv_z;
    d_r_d_pc << s, 0.0, -s * u, 0.0, s, -s * v;
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>{jacobians[0]} = d_r_d_pc * R_cw_;
  }
  return true;
}

}  // namespace asynevo::backend
