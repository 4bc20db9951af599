#pragma once
// WNOA prior between two consecutive knots as a Ceres cost function (12 whitened residuals).
// Residual L·e with e = [Δt ϖ_k − ξ; ϖ_k − J_r⁻¹(ξ) ϖ_{k+1}], ξ = Log(T_k⁻¹ T_{k+1}) and LᵀL = Q(Δt)⁻¹
// (gp/wnoa.hpp; docs/math/gp_backend.md §2). Parameter blocks: {T_k (7), ϖ_k (6), T_{k+1} (7),
// ϖ_{k+1} (6)}, layout in pose_block.hpp.
//
// Scale-free mode (`scale_free`): the translational part of e is homogeneous of degree 1 in the map
// scale (Log's ρ, v and the Q-term of J_r⁻¹ all scale with it), so the prior's cost grows with the square
// of a monocular map's scale, which vision does not constrain: every solve pulls the scale down a little
// (docs/backend.md, "A scale-free prior and a depth gate"). In this mode the returned Jacobian J is replaced
// by J' = J − (J u) wᵀ, u the scale direction of the factor's blocks (scaling about T_k's position) and w the
// part of u orthogonal to the rigid-motion gauge directions, normalized to wᵀu = 1: J'u = 0 (no force along
// the scale), J'g = J g for a rigid motion g, J'd = J d for every d ⟂ w. The residual is unchanged. As
// observability-constrained estimators do (Hesch et al., "Observability-constrained vision-aided inertial
// navigation", 2012), the Jacobian is then deliberately not the derivative of the residual;
// tests/backend/factors_test.cpp checks both properties.

#include <ceres/sized_cost_function.h>

#include <cstdint>

#include "asynevo/gp/wnoa.hpp"

namespace asynevo::backend {

class WnoaPriorFactor final : public ceres::SizedCostFunction<12, 7, 6, 7, 6> {
 public:
  /// `dt` = t_{k+1} − t_k in seconds (> 0); `Q_c` the 6×6 power-spectral density (SPD, any structure).
  WnoaPriorFactor(double dt, const gp::Mat6& Q_c, int series_order = gp::kDefaultSeriesOrder,
                  bool scale_free = false);
  /// Same, from int64-ns knot times.
  WnoaPriorFactor(int64_t t_k_ns, int64_t t_k1_ns, const gp::Mat6& Q_c,
                  int series_order = gp::kDefaultSeriesOrder, bool scale_free = false);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  double dt() const { return dt_; }
  const gp::Mat12& sqrtInformation() const { return sqrt_information_; }

  /// The scale direction u of the four blocks' tangent spaces at these values (24: δT_k, δϖ_k, δT_{k+1},
  /// δϖ_{k+1}; T_k's position is the centre of the scaling, so the pose-k part is zero).
  static Eigen::Matrix<double, 24, 1> scaleDirection(const lie::SE3& T_k, const gp::Vec6& w_k,
                                                     const lie::SE3& T_k1, const gp::Vec6& w_k1);
  /// The rigid-motion gauge directions (24×6: Exp(δ)·T applied to both poses, velocities unchanged).
  static Eigen::Matrix<double, 24, 6> gaugeDirections(const lie::SE3& T_k, const lie::SE3& T_k1);

 private:
  double dt_;
  gp::Mat12 sqrt_information_;
  int series_order_;
  bool scale_free_;
};

}  // namespace asynevo::backend
