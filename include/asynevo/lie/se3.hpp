#pragma once
// SE(3) toolkit: a small rigid-transform type, Exp/Log, hat/vee, curly-hat (ad), adjoint, Q_l and the
// left/right Jacobians with their inverses.
//
// Convention (DESIGN.md §3): T_w_c maps camera to world (p_w = R p_c + t); perturbations are on the
// right, T·Exp(δ); twists are ordered ξ = [ρ; φ] (translation first). Formulas: SER ch. 7 and
// Barfoot & Furgale, TRO 2014, eqs. 100–103 (Q_l), restated in reference/backend.md §1 and derived in
// docs/math/gp_backend.md §1. Small-angle handling: Taylor series of every coefficient.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "asynevo/lie/so3.hpp"

namespace asynevo::lie {

/// A rigid transform (R, t) acting as p ↦ R p + t. R is kept as a rotation matrix; conversion to and
/// from unit quaternions is provided for storage (e.g. Ceres parameter blocks).
class SE3 {
 public:
  SE3() : R_(Mat3::Identity()), t_(Vec3::Zero()) {}
  SE3(const Mat3& R, const Vec3& t) : R_(R), t_(t) {}
  SE3(const Quat& q, const Vec3& t) : R_(q.normalized().toRotationMatrix()), t_(t) {}

  static SE3 identity() { return SE3(); }

  const Mat3& rotation() const { return R_; }
  const Vec3& translation() const { return t_; }
  Quat quaternion() const {
    Quat q(R_);
    q.normalize();
    return q;
  }
  Mat4 matrix() const {
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() = R_;
    m.topRightCorner<3, 1>() = t_;
    return m;
  }

  SE3 inverse() const {
    const Mat3 Rt = R_.transpose();
    return SE3(Rt, -(Rt * t_));
  }
  SE3 operator*(const SE3& other) const { return SE3(R_ * other.R_, R_ * other.t_ + t_); }
  Vec3 operator*(const Vec3& p) const { return R_ * p + t_; }

 private:
  Mat3 R_;
  Vec3 t_;
};

namespace se3 {

/// ξ^ = [φ^ ρ; 0 0] (4×4), ξ = [ρ; φ].
inline Mat4 hat(const Vec6& xi) {
  Mat4 m = Mat4::Zero();
  m.topLeftCorner<3, 3>() = so3::hat(xi.tail<3>());
  m.topRightCorner<3, 1>() = xi.head<3>();
  return m;
}

/// Inverse of hat.
inline Vec6 vee(const Mat4& m) {
  Vec6 xi;
  xi << m.topRightCorner<3, 1>(), so3::vee(m.topLeftCorner<3, 3>());
  return xi;
}

/// Curly hat ξ⋏ = ad(ξ) = [φ^ ρ^; 0 φ^]. Properties: ξ⋏ a = −a⋏ ξ, Ad(Exp ξ) = exp(ξ⋏).
inline Mat6 curlyHat(const Vec6& xi) {
  Mat6 m = Mat6::Zero();
  const Mat3 P = so3::hat(xi.tail<3>());
  m.topLeftCorner<3, 3>() = P;
  m.topRightCorner<3, 3>() = so3::hat(xi.head<3>());
  m.bottomRightCorner<3, 3>() = P;
  return m;
}

/// Adjoint Ad(T) = [R t^R; 0 R], so that T Exp(ξ) T⁻¹ = Exp(Ad(T) ξ).
inline Mat6 adjoint(const SE3& T) {
  Mat6 m = Mat6::Zero();
  const Mat3& R = T.rotation();
  m.topLeftCorner<3, 3>() = R;
  m.topRightCorner<3, 3>() = so3::hat(T.translation()) * R;
  m.bottomRightCorner<3, 3>() = R;
  return m;
}

/// Ad(T⁻¹) = [Rᵀ −Rᵀt^; 0 Rᵀ], without forming T⁻¹.
inline Mat6 adjointInverse(const SE3& T) {
  Mat6 m = Mat6::Zero();
  const Mat3 Rt = T.rotation().transpose();
  m.topLeftCorner<3, 3>() = Rt;
  m.topRightCorner<3, 3>() = -Rt * so3::hat(T.translation());
  m.bottomRightCorner<3, 3>() = Rt;
  return m;
}

/// Exp(ξ) = (Exp(φ), J_l(φ) ρ).
inline SE3 exp(const Vec6& xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  const so3::Coefficients k = so3::coefficients(phi.squaredNorm());
  const Mat3 P = so3::hat(phi);
  const Mat3 P2 = P * P;
  const Mat3 R = Mat3::Identity() + k.a * P + k.b * P2;
  const Mat3 Jl = Mat3::Identity() + k.b * P + k.c * P2;
  return SE3(R, Jl * rho);
}

/// Log(T) = [J_l⁻¹(φ) t; φ], φ = Log(R) (quaternion route), θ ∈ [0, π].
inline Vec6 log(const SE3& T) {
  const Vec3 phi = so3::log(T.rotation());
  Vec6 xi;
  xi << so3::leftJacobianInverse(phi) * T.translation(), phi;
  return xi;
}

/// Coefficients of Q_l (Barfoot & Furgale TRO 2014 eq. 102):
///   c1 = (θ − sinθ)/θ³, c2 = (θ² + 2cosθ − 2)/(2θ⁴), c3 = (2θ − 3sinθ + θcosθ)/(2θ⁵).
/// c2 and c3 cancel catastrophically for small θ (c3's numerator is θ⁵/60), so their series are used
/// below θ = 0.1, carried to θ⁶ (truncation < 1e-17).
inline Eigen::Vector3d qLeftCoefficients(double theta_sq) {
  constexpr double kQThresholdSquared = 1e-2;
  if (theta_sq < kQThresholdSquared) {
    const double t2 = theta_sq;
    const double t4 = t2 * t2;
    const double t6 = t4 * t2;
    return {1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0 - t6 / 362880.0,
            1.0 / 24.0 - t2 / 720.0 + t4 / 40320.0 - t6 / 3628800.0,
            1.0 / 120.0 - t2 / 2520.0 + t4 / 120960.0 - t6 / 9979200.0};
  }
  const double theta = std::sqrt(theta_sq);
  const double s = std::sin(theta);
  const double c = std::cos(theta);
  const double t4 = theta_sq * theta_sq;
  return {(theta - s) / (theta_sq * theta), (theta_sq + 2.0 * c - 2.0) / (2.0 * t4),
          (2.0 * theta - 3.0 * s + theta * c) / (2.0 * t4 * theta)};
}

/// Q_l(ξ) = ½ρ^ + c1 (Pρ^ + ρ^P + Pρ^P) + c2 (P²ρ^ + ρ^P² − 3Pρ^P) + c3 (Pρ^P² + P²ρ^P), P = φ^:
/// the top-right block of J_l(ξ).
/// `c` = qLeftCoefficients(‖φ‖²), for a caller that has them.
inline Mat3 qLeft(const Vec6& xi, const Eigen::Vector3d& c) {
  const Mat3 P = so3::hat(xi.tail<3>());
  const Mat3 Rh = so3::hat(xi.head<3>());
  const Mat3 PR = P * Rh;
  const Mat3 RP = Rh * P;
  const Mat3 PRP = PR * P;
  return 0.5 * Rh + c[0] * (PR + RP + PRP) + c[1] * (P * PR + RP * P - 3.0 * PRP) +
         c[2] * (PRP * P + P * PRP);
}
inline Mat3 qLeft(const Vec6& xi) { return qLeft(xi, qLeftCoefficients(xi.tail<3>().squaredNorm())); }

/// J_l(ξ) = [J_l(φ) Q_l(ξ); 0 J_l(φ)].  Exp(ξ + δ) ≈ Exp(J_l δ) Exp(ξ).
inline Mat6 leftJacobian(const Vec6& xi) {
  Mat6 J = Mat6::Zero();
  const Mat3 Jl = so3::leftJacobian(xi.tail<3>());
  J.topLeftCorner<3, 3>() = Jl;
  J.topRightCorner<3, 3>() = qLeft(xi);
  J.bottomRightCorner<3, 3>() = Jl;
  return J;
}

/// J_l⁻¹(ξ) = [J_l⁻¹(φ) −J_l⁻¹(φ) Q_l(ξ) J_l⁻¹(φ); 0 J_l⁻¹(φ)].
inline Mat6 leftJacobianInverse(const Vec6& xi) {
  Mat6 J = Mat6::Zero();
  const Mat3 Jl_inv = so3::leftJacobianInverse(xi.tail<3>());
  J.topLeftCorner<3, 3>() = Jl_inv;
  J.topRightCorner<3, 3>() = -Jl_inv * qLeft(xi) * Jl_inv;
  J.bottomRightCorner<3, 3>() = Jl_inv;
  return J;
}

/// J_r(ξ) = J_l(−ξ).  Exp(ξ + δ) ≈ Exp(ξ) Exp(J_r δ).
inline Mat6 rightJacobian(const Vec6& xi) { return leftJacobian(-xi); }

/// Exp(ξ) and J_r(ξ) together, the trigonometry of the SO(3) part computed once: the same values, bit
/// for bit, as exp(xi) and rightJacobian(xi) (each expression is evaluated as there).
inline SE3 expWithRightJacobian(const Vec6& xi, Mat6& J_r) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  const double theta_sq = phi.squaredNorm();
  const so3::Coefficients k = so3::coefficients(theta_sq);
  const Mat3 P = so3::hat(phi);
  const Mat3 P2 = P * P;
  const Mat3 R = Mat3::Identity() + k.a * P + k.b * P2;
  const Mat3 Jl = Mat3::Identity() + k.b * P + k.c * P2;
  // leftJacobian(−ξ): so3::leftJacobian(−φ) and qLeft(−ξ); ‖−φ‖² = ‖φ‖² exactly.
  const Vec6 minus = -xi;
  const Mat3 Pm = so3::hat(minus.tail<3>());
  const Mat3 Jl_minus = Mat3::Identity() + k.b * Pm + k.c * Pm * Pm;
  J_r.setZero();
  J_r.topLeftCorner<3, 3>() = Jl_minus;
  J_r.topRightCorner<3, 3>() = qLeft(minus, qLeftCoefficients(theta_sq));
  J_r.bottomRightCorner<3, 3>() = Jl_minus;
  return SE3(R, Jl * rho);
}

/// J_r⁻¹(ξ) = J_l⁻¹(−ξ).  Log(Exp(ξ) Exp(δ)) ≈ ξ + J_r⁻¹ δ.
inline Mat6 rightJacobianInverse(const Vec6& xi) { return leftJacobianInverse(-xi); }

/// J_l⁻¹(ξ) and J_r⁻¹(ξ) together, sharing the trigonometry and the products of Q_l: with
/// Q_l(ξ) = O + E split into the parts odd and even under ξ → −ξ (O = ½ρ^ + c1 Pρ^P + c2(P²ρ^ + ρ^P² −
/// 3Pρ^P), E = c1(Pρ^ + ρ^P) + c3(Pρ^P² + P²ρ^P)), Q_l(−ξ) = E − O. Either output may be null.
inline void inverseJacobians(const Vec6& xi, Mat6* J_l_inv, Mat6* J_r_inv) {
  const Vec3 phi = xi.tail<3>();
  const double theta_sq = phi.squaredNorm();
  const so3::Coefficients k = so3::coefficients(theta_sq);
  const Eigen::Vector3d c = qLeftCoefficients(theta_sq);
  const Mat3 P = so3::hat(phi);
  const Mat3 Rh = so3::hat(xi.head<3>());
  const Mat3 PR = P * Rh;
  const Mat3 RP = Rh * P;
  const Mat3 PRP = PR * P;
  const Mat3 P2 = P * P;
  const Mat3 odd = 0.5 * Rh + c[0] * PRP + c[1] * (P * PR + RP * P - 3.0 * PRP);
  const Mat3 even = c[0] * (PR + RP) + c[2] * (PRP * P + P * PRP);
  if (J_l_inv != nullptr) {
    const Mat3 A = Mat3::Identity() - 0.5 * P + k.d * P2;  // J_l⁻¹(φ)
    J_l_inv->setZero();
    J_l_inv->topLeftCorner<3, 3>() = A;
    J_l_inv->topRightCorner<3, 3>() = -A * (odd + even) * A;
    J_l_inv->bottomRightCorner<3, 3>() = A;
  }
  if (J_r_inv != nullptr) {
    const Mat3 A = Mat3::Identity() + 0.5 * P + k.d * P2;  // J_r⁻¹(φ) = J_l⁻¹(−φ)
    J_r_inv->setZero();
    J_r_inv->topLeftCorner<3, 3>() = A;
    J_r_inv->topRightCorner<3, 3>() = -A * (even - odd) * A;
    J_r_inv->bottomRightCorner<3, 3>() = A;
  }
}

/// Right-perturbation difference: Log(T_b⁻¹ T_a), the inverse of the retraction T_b·Exp(δ).
inline Vec6 boxMinus(const SE3& T_a, const SE3& T_b) { return log(T_b.inverse() * T_a); }

}  // namespace se3
}  // namespace asynevo::lie
