#include "asynevo/backend/factors/wnoa_prior_factor.hpp"

#include <Eigen/Core>

#include "asynevo/backend/factors/pose_block.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo::backend {

WnoaPriorFactor::WnoaPriorFactor(double dt, const gp::Mat6& Q_c, int series_order)
    : dt_(dt),
      sqrt_information_(gp::sqrtInformation(dt, gp::qcSqrtInformation(Q_c))),
      series_order_(series_order) {}

WnoaPriorFactor::WnoaPriorFactor(int64_t t_k_ns, int64_t t_k1_ns, const gp::Mat6& Q_c, int series_order)
    : WnoaPriorFactor(durationSeconds(t_k_ns, t_k1_ns), Q_c, series_order) {}

bool WnoaPriorFactor::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const lie::SE3 T_k = poseFromBlock(parameters[0]);
  const Eigen::Map<const gp::Vec6> w_k(parameters[1]);
  const lie::SE3 T_k1 = poseFromBlock(parameters[2]);
  const Eigen::Map<const gp::Vec6> w_k1(parameters[3]);

  const bool any_jacobian = jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr ||
                                                     jacobians[2] != nullptr || jacobians[3] != nullptr);
  gp::PriorJacobians J;
  const gp::Vec12 e = gp::priorError(T_k, w_k, T_k1, w_k1, dt_, any_jacobian ? &J : nullptr, series_order_);
  Eigen::Map<gp::Vec12>{residuals} = sqrt_information_ * e;
  if (!any_jacobian) return true;

  using VelocityJacobian = Eigen::Map<Eigen::Matrix<double, 12, 6, Eigen::RowMajor>>;
  if (jacobians[0] != nullptr) setPoseJacobian<12>(jacobians[0], sqrt_information_ * J.d_e_d_pose_k);
  if (jacobians[1] != nullptr) VelocityJacobian{jacobians[1]} = sqrt_information_ * J.d_e_d_vel_k;
  if (jacobians[2] != nullptr) setPoseJacobian<12>(jacobians[2], sqrt_information_ * J.d_e_d_pose_k1);
  if (jacobians[3] != nullptr) VelocityJacobian{jacobians[3]} = sqrt_information_ * J.d_e_d_vel_k1;
  return true;
}

}  // namespace asynevo::backend
