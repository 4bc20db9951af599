#pragma once
// Prior on one knot state (pose and velocity), used before any marginalization prior exists
// (initial-state prior, reference/backend.md §2):
//   e = [Log(T̆⁻¹ T); ϖ − ϖ̆],  residual L·e with LᵀL = P̆⁻¹,
//   ∂e/∂δ = [J_r⁻¹(Log(T̆⁻¹T)); 0],  ∂e/∂ϖ = [0; I].
// Parameter blocks: {T (7), ϖ (6)}. docs/math/gp_backend.md §5.

#include <ceres/sized_cost_function.h>

#include "asynevo/gp/wnoa.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {

class StatePriorFactor final : public ceres::SizedCostFunction<12, 7, 6> {
 public:
  /// `covariance` is the 12×12 covariance P̆ of [δ; ϖ] (SPD), in the tangent order [ρ; φ; v; ω].
  StatePriorFactor(const lie::SE3& T_prior, const lie::Vec6& w_prior, const gp::Mat12& covariance);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  const gp::Mat12& sqrtInformation() const { return sqrt_information_; }

 private:
  lie::SE3 T_prior_inv_;
  lie::Vec6 w_prior_;
  gp::Mat12 sqrt_information_;
};

}  // namespace asynevo::backend
