#include "asynevo/backend/factors/state_prior_factor.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "asynevo/backend/factors/pose_block.hpp"

namespace asynevo::backend {

StatePriorFactor::StatePriorFactor(const lie::SE3& T_prior, const lie::Vec6& w_prior,
                                   const gp::Mat12& covariance)
    : T_prior_inv_(T_prior.inverse()), w_prior_(w_prior) {
  const gp::Mat12 information = covariance.inverse();
  const Eigen::LLT<gp::Mat12> llt(0.5 * (information + information.transpose()));
  sqrt_information_ = llt.matrixU();  // UᵀU = P̆⁻¹
}

bool StatePriorFactor::Evaluate(double const* const* parameters, double* residuals,
                                double** jacobians) const {
  const lie::Vec6 d_pose = lie::se3::log(T_prior_inv_ * poseFromBlock(parameters[0]));
  gp::Vec12 e;
  e << d_pose, Eigen::Map<const lie::Vec6>(parameters[1]) - w_prior_;
  Eigen::Map<gp::Vec12>{residuals} = sqrt_information_ * e;
  if (jacobians == nullptr) return true;
  if (jacobians[0] != nullptr) {
    setPoseJacobian<12>(jacobians[0],
                        sqrt_information_.leftCols<6>() * lie::se3::rightJacobianInverse(d_pose));
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 12, 6, Eigen::RowMajor>>{jacobians[1]} =
        sqrt_information_.rightCols<6>();
  }
  return true;
}

}  // namespace asynevo::backend
