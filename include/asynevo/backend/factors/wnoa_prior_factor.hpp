#pragma once
// WNOA prior between two consecutive knots as a Ceres cost function (12 whitened residuals).
// Residual L·e with e = [Δt ϖ_k − ξ; ϖ_k − J_r⁻¹(ξ) ϖ_{k+1}], ξ = Log(T_k⁻¹ T_{k+1}) and LᵀL = Q(Δt)⁻¹
// (gp/wnoa.hpp; docs/math/gp_backend.md §2). Parameter blocks: {T_k (7), ϖ_k (6), T_{k+1} (7),
// ϖ_{k+1} (6)}, layout in pose_block.hpp.

#include <ceres/sized_cost_function.h>

#include <cstdint>

#include "asynevo/gp/wnoa.hpp"

namespace asynevo::backend {

class WnoaPriorFactor final : public ceres::SizedCostFunction<12, 7, 6, 7, 6> {
 public:
  /// `dt` = t_{k+1} − t_k in seconds (> 0); `Q_c` the 6×6 power-spectral density (SPD, any structure).
  WnoaPriorFactor(double dt, const gp::Mat6& Q_c, int series_order = gp::kDefaultSeriesOrder);
  /// Same, from int64-ns knot times.
  WnoaPriorFactor(int64_t t_k_ns, int64_t t_k1_ns, const gp::Mat6& Q_c,
                  int series_order = gp::kDefaultSeriesOrder);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  double dt() const { return dt_; }
  const gp::Mat12& sqrtInformation() const { return sqrt_information_; }

 private:
  double dt_;
  gp::Mat12 sqrt_information_;
  int series_order_;
};

}  // namespace asynevo::backend
