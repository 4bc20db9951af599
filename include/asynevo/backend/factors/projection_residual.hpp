#pragma once
// The whitened pinhole residual shared by the projection factors (reference/backend.md §4):
//   r = (π(p_c) − z)/σ,  π(p) = [p_x/p_z, p_y/p_z],  ∂r/∂p_c = (1/σ) Jπ,  Jπ = [1/z 0 −x/z²; 0 1/z −y/z²].

#include <Eigen/Core>

namespace asynevo::backend {

/// Writes r (2 values); returns false, writing nothing, when p_c is not in front of the camera
/// (p_c,z ≤ min_depth, NaN included). `d_r_d_pc` may be null.
inline bool projectionResidual(const Eigen::Vector3d& p_c, const Eigen::Vector2d& z, double inv_sigma, double min_depth,
                               double* residuals, Eigen::Matrix<double, 2, 3>* d_r_d_pc) {
  if (!(p_c.z() > min_depth)) return false;
  const double inv_z = 1.0 / p_c.z();
  const double u = p_c.x() * inv_z;
  const double v = p_c.y() * inv_z;
  residuals[0] = (u - z.x()) * inv_sigma;
  residuals[1] = (v - z.y()) * inv_sigma;
  if (d_r_d_pc != nullptr) {
    const double s = inv_sigma * inv_z;
    *d_r_d_pc << s, 0.0, -s * u, 0.0, s, -s * v;
  }
  return true;
}

}  // namespace asynevo::backend
