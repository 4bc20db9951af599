#pragma once
// SE(3) manifold for Ceres pose blocks [t; q_xyzw] with the right retraction T·Exp(δ), δ = [ρ; φ].
// See pose_block.hpp for the tangent-Jacobian convention (PlusJacobian = [I₆; 0]).

#include <ceres/manifold.h>

namespace asynevo::backend {

class SE3Manifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  /// x ⊞ δ = T(x)·Exp(δ), stored with a unit quaternion (q_w ≥ 0 is not enforced; both covers work).
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  /// [I₆; 0₁ₓ₆] (row-major 7×6): tangent-Jacobian convention, see pose_block.hpp.
  bool PlusJacobian(const double* x, double* jacobian) const override;
  /// y ⊟ x = Log(T(x)⁻¹ T(y)), the exact inverse of Plus.
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  /// [I₆ 0₆ₓ₁] (row-major 6×7), consistent with PlusJacobian (MinusJacobian·PlusJacobian = I).
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace asynevo::backend
