#include "asynevo/backend/factors/wnoa_prior_factor.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>

#include "asynevo/backend/factors/pose_block.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo::backend {

WnoaPriorFactor::WnoaPriorFactor(double dt, const gp::Mat6& Q_c, int series_order, bool scale_free)
    : dt_(dt),
      sqrt_information_(gp::sqrtInformation(dt, gp::qcSqrtInformation(Q_c))),
      series_order_(series_order),
      scale_free_(scale_free) {}

WnoaPriorFactor::WnoaPriorFactor(int64_t t_k_ns, int64_t t_k1_ns, const gp::Mat6& Q_c, int series_order,
                                 bool scale_free)
    : WnoaPriorFactor(durationSeconds(t_k_ns, t_k1_ns), Q_c, series_order, scale_free) {}

Eigen::Matrix<double, 24, 1> WnoaPriorFactor::scaleDirection(const lie::SE3& T_k, const gp::Vec6& w_k,
                                                             const lie::SE3& T_k1, const gp::Vec6& w_k1) {
  // Scaling the map by (1 + ε) about T_k's position moves T_{k+1} to T_{k+1}·Exp(ε [R_{k+1}ᵀ(t_{k+1} − t_k);
  // 0]) and multiplies the linear velocities by (1 + ε).
  Eigen::Matrix<double, 24, 1> u = Eigen::Matrix<double, 24, 1>::Zero();
  u.segment<3>(6) = w_k.head<3>();
  u.segment<3>(12) = T_k1.rotation().transpose() * (T_k1.translation() - T_k.translation());
  u.segment<3>(18) = w_k1.head<3>();
  return u;
}

Eigen::Matrix<double, 24, 6> WnoaPriorFactor::gaugeDirections(const lie::SE3& T_k, const lie::SE3& T_k1) {
  // Exp(δ)·T = T·Exp(Ad(T⁻¹) δ): in right-perturbation coordinates a world motion δ is Ad(T⁻¹) δ.
  Eigen::Matrix<double, 24, 6> G = Eigen::Matrix<double, 24, 6>::Zero();
  G.block<6, 6>(0, 0) = lie::se3::adjointInverse(T_k);
  G.block<6, 6>(12, 0) = lie::se3::adjointInverse(T_k1);
  return G;
}

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

  Eigen::Matrix<double, 12, 24> Jt;
  Jt << sqrt_information_ * J.d_e_d_pose_k, sqrt_information_ * J.d_e_d_vel_k,
      sqrt_information_ * J.d_e_d_pose_k1, sqrt_information_ * J.d_e_d_vel_k1;
  if (scale_free_) {
    const Eigen::Matrix<double, 24, 1> u = scaleDirection(T_k, w_k, T_k1, w_k1);
    const Eigen::Matrix<double, 24, 6> G = gaugeDirections(T_k, T_k1);
    const Eigen::Matrix<double, 24, 1> w = u - G * (G.transpose() * G).ldlt().solve(G.transpose() * u);
    const double wu = w.dot(u);
    // wu = |w|² is 0 only for a map without translation (u in the gauge span): nothing to project then.
    if (wu > 1e-12 * std::max(1.0, u.squaredNorm())) Jt -= (Jt * u) * (w.transpose() / wu);
  }
  using VelocityJacobian = Eigen::Map<Eigen::Matrix<double, 12, 6, Eigen::RowMajor>>;
  if (jacobians[0] != nullptr) setPoseJacobian<12>(jacobians[0], Jt.middleCols<6>(0));
  if (jacobians[1] != nullptr) VelocityJacobian{jacobians[1]} = Jt.middleCols<6>(6);
  if (jacobians[2] != nullptr) setPoseJacobian<12>(jacobians[2], Jt.middleCols<6>(12));
  if (jacobians[3] != nullptr) VelocityJacobian{jacobians[3]} = Jt.middleCols<6>(18);
  return true;
}

}  // namespace asynevo::backend
