#pragma once
// Monocular scale anchor: the distance between two knot positions is held at a fixed value,
//   r = (‖t_b − t_a‖ − d) / σ,
// so the map scale chosen at initialization (unit baseline) cannot collapse under the WNOA prior, which
// is not scale invariant and pulls a monocular map toward zero scale (reference/backend.md §2, "Gauge").
// With the right perturbation T·Exp([ρ; φ]) the translation moves by Rρ to first order and not with φ:
//   ∂r/∂δ_b = (1/σ) [uᵀR_b, 0],  ∂r/∂δ_a = −(1/σ) [uᵀR_a, 0],  u = (t_b − t_a)/‖t_b − t_a‖.
// Parameter blocks: {T_a (7), T_b (7)} (tangent-Jacobian convention, pose_block.hpp).

#include <ceres/sized_cost_function.h>

namespace asynevo::backend {

class ScaleAnchorFactor final : public ceres::SizedCostFunction<1, 7, 7> {
 public:
  ScaleAnchorFactor(double distance, double sigma) : distance_(distance), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  double distance_;
  double inv_sigma_;
};

}  // namespace asynevo::backend
