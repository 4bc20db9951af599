#include "asynevo/backend/factors/gp_projection_factor.hpp"

#include "asynevo/backend/factors/pose_block.hpp"
#include "asynevo/backend/factors/projection_residual.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo::backend {

GpProjectionFactor::GpProjectionFactor(const Eigen::Vector2d& z, const gp::InterpolationWeights& weights,
                                       double sigma, double min_depth, int series_order)
    : z_(z), weights_(weights), inv_sigma_(1.0 / sigma), min_depth_(min_depth), series_order_(series_order) {}

GpProjectionFactor::GpProjectionFactor(const Eigen::Vector2d& z, int64_t t_ns, int64_t t_k_ns,
                                       int64_t t_k1_ns, double sigma, double min_depth, int series_order)
    : GpProjectionFactor(
          z, gp::interpolationWeights(durationSeconds(t_k_ns, t_ns), durationSeconds(t_k_ns, t_k1_ns)), sigma,
          min_depth, series_order) {}

bool GpProjectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  const bool any_jacobian =
      jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr ||
                               jacobians[2] != nullptr || jacobians[3] != nullptr || jacobians[4] != nullptr);
  const Eigen::Map<const gp::Vec6> w_k(parameters[1]);
  const lie::SE3 T_k = poseFromBlock(parameters[0]);
  // The segment's terms: shared through the cache when there is one, else computed here.
  std::shared_ptr<const gp::SegmentTerms> shared;
  gp::SegmentTerms own;
  if (cache_) {
    shared = cache_->terms(parameters[0], parameters[2], parameters[3], any_jacobian, series_order_);
  } else {
    own = gp::segmentTerms(T_k, poseFromBlock(parameters[2]), Eigen::Map<const gp::Vec6>(parameters[3]), any_jacobian,
                           series_order_);
  }
  const gp::PoseInterpolator interp(T_k, w_k, shared ? *shared : own, weights_, any_jacobian);
  const lie::SE3& T_tau = interp.pose();
  const Eigen::Map<const Eigen::Vector3d> p_w(parameters[4]);
  const Eigen::Matrix3d R_t = T_tau.rotation().transpose();
  const Eigen::Vector3d p_c = R_t * (p_w - T_tau.translation());
  Eigen::Matrix<double, 2, 3> d_r_d_pc;
  if (!projectionResidual(p_c, z_, inv_sigma_, min_depth_, residuals, any_jacobian ? &d_r_d_pc : nullptr))
    return false;  // cheirality (also rejects NaN)
  if (!any_jacobian) return true;

  if (jacobians[4] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>{jacobians[4]} = d_r_d_pc * R_t;
  }
  // ∂r/∂δ_τ = (1/σ) Jπ [−I₃, p_c^].
  Eigen::Matrix<double, 2, 6> d_r_d_tau;
  d_r_d_tau.leftCols<3>() = -d_r_d_pc;
  d_r_d_tau.rightCols<3>() = d_r_d_pc * lie::so3::hat(p_c);

  Eigen::Matrix<double, 2, 6> d_pose_k;
  Eigen::Matrix<double, 2, 6> d_vel_k;
  Eigen::Matrix<double, 2, 6> d_pose_k1;
  Eigen::Matrix<double, 2, 6> d_vel_k1;
  interp.chain<2>(
      d_r_d_tau, jacobians[0] != nullptr ? &d_pose_k : nullptr, jacobians[1] != nullptr ? &d_vel_k : nullptr,
      jacobians[2] != nullptr ? &d_pose_k1 : nullptr, jacobians[3] != nullptr ? &d_vel_k1 : nullptr);
  using VelocityJacobian = Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>>;
  if (jacobians[0] != nullptr) setPoseJacobian<2>(jacobians[0], d_pose_k);
  if (jacobians[1] != nullptr) VelocityJacobian{jacobians[1]} = d_vel_k;
  if (jacobians[2] != nullptr) setPoseJacobian<2>(jacobians[2], d_pose_k1);
  if (jacobians[3] != nullptr) VelocityJacobian{jacobians[3]} = d_vel_k1;
  return true;
}

}  // namespace asynevo::backend
