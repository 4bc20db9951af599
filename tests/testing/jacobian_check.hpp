#pragma once
// Numerical Jacobian checker for Ceres cost functions that perturbs through each block's own
// Manifold::Plus (reference/backend.md §6: ceres::GradientChecker differentiates in ambient
// coordinates and would report false mismatches under the tangent-Jacobian convention).
//
// For block i with manifold M_i (Euclidean when null) the checked quantity is the tangent Jacobian
//   analytic:  J_ambient · M_i.PlusJacobian(x_i)        (exactly what the solver uses)
//   numeric:   [r(x_i ⊞ h e_k) − r(x_i ⊞ −h e_k)] / 2h,  k = 1..tangent size.

#include <ceres/cost_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace asynevo::testing {

struct JacobianCheckResult {
  bool evaluated = false;                 // all evaluations succeeded
  std::vector<double> max_abs_error;      // per block, tangent Jacobian
  std::vector<double> max_abs_numeric;    // per block, scale of the numeric Jacobian
  std::vector<Eigen::MatrixXd> analytic;  // per block, residuals × tangent size
  std::vector<Eigen::MatrixXd> numeric;

  double worstError() const {
    double e = 0.0;
    for (double v : max_abs_error) e = std::max(e, v);
    return e;
  }
  std::string report() const {
    std::ostringstream out;
    for (size_t i = 0; i < max_abs_error.size(); ++i) {
      out << "block " << i << ": max |analytic − numeric| = " << max_abs_error[i]
          << " (max |numeric| = " << max_abs_numeric[i] << ")\n";
    }
    return out.str();
  }
};

/// `values[i]` holds block i (ambient size); `manifolds[i]` may be null (Euclidean). Constant blocks are
/// not special: every block is checked.
inline JacobianCheckResult checkJacobians(const ceres::CostFunction& cost,
                                          const std::vector<std::vector<double>>& values,
                                          const std::vector<const ceres::Manifold*>& manifolds,
                                          double step = 1e-6) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  const int num_blocks = static_cast<int>(sizes.size());
  const int m = cost.num_residuals();
  JacobianCheckResult result;

  std::vector<const double*> params(num_blocks);
  for (int i = 0; i < num_blocks; ++i) params[i] = values[i].data();

  // Analytic, ambient.
  std::vector<RowMajor> ambient(num_blocks);
  std::vector<double*> jac_ptrs(num_blocks);
  for (int i = 0; i < num_blocks; ++i) {
    ambient[i].setZero(m, sizes[i]);
    jac_ptrs[i] = ambient[i].data();
  }
  Eigen::VectorXd r0(m);
  if (!cost.Evaluate(params.data(), r0.data(), jac_ptrs.data())) return result;

  result.evaluated = true;
  for (int i = 0; i < num_blocks; ++i) {
    const ceres::Manifold* manifold = manifolds.size() > static_cast<size_t>(i) ? manifolds[i] : nullptr;
    const int tangent = manifold != nullptr ? manifold->TangentSize() : sizes[i];
    Eigen::MatrixXd analytic = ambient[i];
    if (manifold != nullptr) {
      RowMajor plus_jacobian(sizes[i], tangent);
      manifold->PlusJacobian(values[i].data(), plus_jacobian.data());
      analytic = ambient[i] * plus_jacobian;
    }
    Eigen::MatrixXd numeric(m, tangent);
    std::vector<double> x_plus(sizes[i]);
    std::vector<double> x_minus(sizes[i]);
    for (int k = 0; k < tangent; ++k) {
      Eigen::VectorXd delta = Eigen::VectorXd::Zero(tangent);
      delta[k] = step;
      if (manifold != nullptr) {
        manifold->Plus(values[i].data(), delta.data(), x_plus.data());
        delta[k] = -step;
        manifold->Plus(values[i].data(), delta.data(), x_minus.data());
      } else {
        x_plus = values[i];
        x_minus = values[i];
        x_plus[k] += step;
        x_minus[k] -= step;
      }
      Eigen::VectorXd r_plus(m);
      Eigen::VectorXd r_minus(m);
      std::vector<const double*> p = params;
      p[i] = x_plus.data();
      bool ok = cost.Evaluate(p.data(), r_plus.data(), nullptr);
      p[i] = x_minus.data();
      ok = ok && cost.Evaluate(p.data(), r_minus.data(), nullptr);
      if (!ok) {
        result.evaluated = false;
        return result;
      }
      numeric.col(k) = (r_plus - r_minus) / (2.0 * step);
    }
    result.max_abs_error.push_back((analytic - numeric).cwiseAbs().maxCoeff());
    result.max_abs_numeric.push_back(numeric.cwiseAbs().maxCoeff());
    result.analytic.push_back(analytic);
    result.numeric.push_back(numeric);
  }
  return result;
}

}  // namespace asynevo::testing
