#pragma once
// White-noise-on-acceleration (WNOA) Gaussian-process prior on SE(3): transition Φ, covariance Q(Δt),
// its inverse and closed-form square-root information, the series Jacobians of J_r⁻¹(ξ)ϖ and J_r(ξ)v,
// and the prior error between two knots with its analytic Jacobians.
//
// Sources: Anderson & Barfoot, IROS 2015 ("Full STEAM ahead"); Anderson, Barfoot, Tong, Särkkä, AURO
// 2015; the AsynEVO paper's e(x_k, x_{k+1}) (Wang et al., arXiv 2402.16398). All formulas restated in
// our convention (right perturbation, ξ = [ρ; φ], body twist ϖ with Ṫ = Tϖ^) in reference/backend.md
// §2 and derived in docs/math/gp_backend.md §2.
//
// Pure functions: no I/O, no allocation, no state.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "asynevo/lie/se3.hpp"

namespace asynevo::gp {

using lie::Mat3;
using lie::Mat6;
using lie::SE3;
using lie::Vec3;
using lie::Vec6;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat12x6 = Eigen::Matrix<double, 12, 6>;

/// Order of the power series used for ∂(J_r⁻¹(ξ)ϖ)/∂ξ (and ∂(J_r(ξ)v)/∂ξ). 1 is STEAM's first-order
/// approximation (M ≈ −½ϖ⋏); 2 is the recommended default (reference/backend.md §2); higher orders are
/// available for accuracy studies (the series of J_r⁻¹ converges for ‖φ‖ < 2π).
constexpr int kDefaultSeriesOrder = 2;
constexpr int kMaxSeriesOrder = 8;

/// Φ(t + Δt, t) = [I ΔtI; 0 I] (12×12, state [ξ; ξ̇]).
inline Mat12 transition(double dt) {
  Mat12 phi = Mat12::Identity();
  phi.topRightCorner<6, 6>().diagonal().setConstant(dt);
  return phi;
}

/// Q(Δt) = [Δt³/3 Q_c, Δt²/2 Q_c; Δt²/2 Q_c, Δt Q_c].
inline Mat12 covariance(double dt, const Mat6& Q_c) {
  Mat12 Q;
  Q << (dt * dt * dt / 3.0) * Q_c, (dt * dt / 2.0) * Q_c,  //
      (dt * dt / 2.0) * Q_c, dt * Q_c;
  return Q;
}

/// Q(Δt)⁻¹ = [12/Δt³ Q_c⁻¹, −6/Δt² Q_c⁻¹; −6/Δt² Q_c⁻¹, 4/Δt Q_c⁻¹].
inline Mat12 information(double dt, const Mat6& Q_c_inv) {
  Mat12 Q_inv;
  Q_inv << (12.0 / (dt * dt * dt)) * Q_c_inv, (-6.0 / (dt * dt)) * Q_c_inv,  //
      (-6.0 / (dt * dt)) * Q_c_inv, (4.0 / dt) * Q_c_inv;
  return Q_inv;
}

/// U (upper triangular) with UᵀU = Q_c⁻¹. For diagonal Q_c = diag(q_i), U = diag(q_i^{-1/2}).
/// Q_c must be symmetric positive definite.
inline Mat6 qcSqrtInformation(const Mat6& Q_c) {
  const Mat6 Q_c_inv = Q_c.inverse();
  const Eigen::LLT<Mat6> llt(0.5 * (Q_c_inv + Q_c_inv.transpose()));
  return llt.matrixU();
}

/// Square-root information L (12×12) with LᵀL = Q(Δt)⁻¹, in closed form from U (UᵀU = Q_c⁻¹):
///   L = [ √12 Δt^{-3/2} U   −√3 Δt^{-1/2} U ]
///       [ 0                  Δt^{-1/2} U     ]
/// (reference/backend.md §2; for diagonal Q_c this is the per-axis form w_i, w_{6+i}.)
inline Mat12 sqrtInformation(double dt, const Mat6& U) {
  const double inv_sqrt_dt = 1.0 / std::sqrt(dt);
  Mat12 L = Mat12::Zero();
  L.topLeftCorner<6, 6>() = (std::sqrt(12.0) * inv_sqrt_dt / dt) * U;
  L.topRightCorner<6, 6>() = (-std::sqrt(3.0) * inv_sqrt_dt) * U;
  L.bottomRightCorner<6, 6>() = inv_sqrt_dt * U;
  return L;
}

/// ∂f/∂ξ for f(ξ) = Σ_{n=1}^{K} c_n (ξ⋏)ⁿ v, exactly for the truncated series.
/// With X = ξ⋏ and u_m = Xᵐ v:  ∂(Xⁿv)/∂ξ = −Σ_{j<n} Xʲ (u_{n−1−j})⋏, so by Horner
///   ∂f/∂ξ = −(C_0 + X(C_1 + X(C_2 + …))),  C_j = (Σ_{n>j} c_n u_{n−1−j})⋏.
/// (docs/math/gp_backend.md §2.3.)
/// `order` is clamped to [1, kMaxSeriesOrder].
inline Mat6 seriesDerivative(const Vec6& xi, const Vec6& v, const double* c, int order) {
  order = std::clamp(order, 1, kMaxSeriesOrder);
  const Mat6 X = lie::se3::curlyHat(xi);
  Vec6 u[kMaxSeriesOrder];
  u[0] = v;
  for (int m = 1; m < order; ++m) u[m] = X * u[m - 1];
  Mat6 acc = Mat6::Zero();
  for (int j = order - 1; j >= 0; --j) {
    Vec6 s = Vec6::Zero();
    for (int n = j + 1; n <= order; ++n) s += c[n] * u[n - 1 - j];
    acc = (j == order - 1) ? lie::se3::curlyHat(s) : Mat6(lie::se3::curlyHat(s) + X * acc);
  }
  return -acc;
}

/// M = ∂(J_r⁻¹(ξ) w)/∂ξ from J_r⁻¹(ξ) = Σ Bₙ/n! (−ξ⋏)ⁿ = I + ½ξ⋏ + (1/12)(ξ⋏)² − (1/720)(ξ⋏)⁴ + …
/// Order 2: M ≈ −½w⋏ − (1/12)[(ξ⋏w)⋏ + ξ⋏w⋏] (the cubic term vanishes, B₃ = 0).
inline Mat6 dJrInvTimesVecDxi(const Vec6& xi, const Vec6& w, int order = kDefaultSeriesOrder) {
  // c_n = Bₙ (−1)ⁿ / n!, n = 0..8.
  static constexpr double kC[kMaxSeriesOrder + 1] = {
      1.0, 0.5, 1.0 / 12.0, 0.0, -1.0 / 720.0, 0.0, 1.0 / 30240.0, 0.0, -1.0 / 1209600.0};
  return seriesDerivative(xi, w, kC, order);
}

/// N = ∂(J_r(ξ) v)/∂ξ from J_r(ξ) = Σ (−ξ⋏)ⁿ/(n+1)!.  Order 2: N ≈ ½v⋏ − (1/6)[(ξ⋏v)⋏ + ξ⋏v⋏].
inline Mat6 dJrTimesVecDxi(const Vec6& xi, const Vec6& v, int order = kDefaultSeriesOrder) {
  // c_n = (−1)ⁿ/(n+1)!, n = 0..8.
  static constexpr double kC[kMaxSeriesOrder + 1] = {1.0,          -0.5,           1.0 / 6.0,
                                                     -1.0 / 24.0,  1.0 / 120.0,    -1.0 / 720.0,
                                                     1.0 / 5040.0, -1.0 / 40320.0, 1.0 / 362880.0};
  return seriesDerivative(xi, v, kC, order);
}

/// Jacobians of the 12-vector prior error w.r.t. right pose perturbations δ_k, δ_{k+1} and additive
/// velocity perturbations.
struct PriorJacobians {
  Mat12x6 d_e_d_pose_k;
  Mat12x6 d_e_d_vel_k;
  Mat12x6 d_e_d_pose_k1;
  Mat12x6 d_e_d_vel_k1;
};

/// WNOA prior error between knots k and k+1 (AsynEVO sign convention):
///   ξ = Log(T_k⁻¹ T_{k+1}),  e = [Δt ϖ_k − ξ ;  ϖ_k − J_r⁻¹(ξ) ϖ_{k+1}],  cost ½ eᵀQ(Δt)⁻¹e.
/// Jacobians (reference/backend.md §2; docs/math/gp_backend.md §2.2), with A1 = J_l⁻¹(ξ),
/// J⁻¹ = J_r⁻¹(ξ), M = ∂(J_r⁻¹(ξ)ϖ_{k+1})/∂ξ:
///            δ_k      ϖ_k     δ_{k+1}    ϖ_{k+1}
///   e1       A1       Δt I    −J⁻¹       0
///   e2       M·A1     I       −M·J⁻¹     −J⁻¹
inline Vec12 priorError(const SE3& T_k, const Vec6& w_k, const SE3& T_k1, const Vec6& w_k1, double dt,
                        PriorJacobians* jacobians = nullptr, int series_order = kDefaultSeriesOrder) {
  const Vec6 xi = lie::se3::log(T_k.inverse() * T_k1);
  Mat6 J_inv;
  Mat6 A1;
  lie::se3::inverseJacobians(xi, jacobians != nullptr ? &A1 : nullptr, &J_inv);
  Vec12 e;
  e.head<6>() = dt * w_k - xi;
  e.tail<6>() = w_k - J_inv * w_k1;
  if (jacobians != nullptr) {
    const Mat6 M = dJrInvTimesVecDxi(xi, w_k1, series_order);
    jacobians->d_e_d_pose_k << A1, M * A1;
    jacobians->d_e_d_vel_k << dt * Mat6::Identity(), Mat6::Identity();
    jacobians->d_e_d_pose_k1 << -J_inv, -M * J_inv;
    jacobians->d_e_d_vel_k1 << Mat6::Zero(), -J_inv;
  }
  return e;
}

}  // namespace asynevo::gp
