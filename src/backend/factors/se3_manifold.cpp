#include "asynevo/backend/factors/se3_manifold.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "asynevo/backend/factors/pose_block.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

bool SE3Manifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  // T·Exp(δ) = (R Exp(φ), t + R J_l(φ) ρ) (docs/math/gp_backend.md §5).
  const Eigen::Map<const Eigen::Vector3d> t(x);
  const Eigen::Map<const Eigen::Quaterniond> q(x + 3);
  const Eigen::Map<const Eigen::Vector3d> rho(delta);
  const Eigen::Map<const Eigen::Vector3d> phi(delta + 3);
  const Eigen::Quaterniond q_unit = q.normalized();
  Eigen::Map<Eigen::Vector3d> t_out(x_plus_delta);
  Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta + 3);
  t_out = t + q_unit * (lie::so3::leftJacobian(phi) * rho);
  q_out = (q_unit * lie::so3::expQuaternion(phi)).normalized();
  return true;
}

bool SE3Manifold::PlusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topRows<6>().setIdentity();
  return true;
}

bool SE3Manifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<Eigen::Matrix<double, 6, 1>> d(y_minus_x);
  d = lie::se3::boxMinus(poseFromBlock(y), poseFromBlock(x));
  return true;
}

bool SE3Manifold::MinusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.leftCols<6>().setIdentity();
  return true;
}

}  // namespace asynevo::backend
