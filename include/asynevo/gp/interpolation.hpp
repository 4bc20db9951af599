#pragma once
// GP interpolation between two WNOA knots: the weights Λ(τ), Ψ(τ) (closed cubic-Hermite form and the
// general matrix formula), the interpolated pose and body velocity, and their analytic Jacobians.
//
// Sources: Barfoot, Tong, Särkkä RSS 2014 / Anderson et al. AURO 2015 (sparse GP interpolation),
// STEAM's const_vel pose/velocity interpolators (formulas only), restated in our convention in
// reference/backend.md §3 and derived in docs/math/gp_backend.md §3.

#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <optional>

#include "asynevo/gp/wnoa.hpp"
#include "asynevo/lie/se3.hpp"

namespace asynevo::gp {

/// Scalar interpolation weights: Λ = Λ̃ ⊗ I₆, Ψ = Ψ̃ ⊗ I₆ for any constant Q_c (Q_c cancels).
struct InterpolationWeights {
  double lambda11 = 1.0;
  double lambda12 = 0.0;
  double lambda21 = 0.0;
  double lambda22 = 1.0;
  double psi11 = 0.0;
  double psi12 = 0.0;
  double psi21 = 0.0;
  double psi22 = 0.0;
};

/// Closed form with s = τ/Δt (τ = t − t_k in seconds, 0 ≤ τ ≤ Δt):
///   Ψ11 = 3s² − 2s³        Ψ12 = Δt(s³ − s²)         Ψ21 = 6(s − s²)/Δt    Ψ22 = 3s² − 2s
///   Λ11 = 1 − 3s² + 2s³    Λ12 = Δt(s − 2s² + s³)    Λ21 = −6(s − s²)/Δt   Λ22 = (1 − s)(1 − 3s)
/// Depends on times only: compute once per measurement.
inline InterpolationWeights interpolationWeights(double tau, double dt) {
  const double s = std::clamp(tau / dt, 0.0, 1.0);
  const double s2 = s * s;
  const double s3 = s2 * s;
  InterpolationWeights w;
  w.psi11 = 3.0 * s2 - 2.0 * s3;
  w.psi12 = dt * (s3 - s2);
  w.psi21 = 6.0 * (s - s2) / dt;
  w.psi22 = 3.0 * s2 - 2.0 * s;
  w.lambda11 = 1.0 - 3.0 * s2 + 2.0 * s3;
  w.lambda12 = dt * (s - 2.0 * s2 + s3);
  w.lambda21 = -6.0 * (s - s2) / dt;
  w.lambda22 = (1.0 - s) * (1.0 - 3.0 * s);
  return w;
}

/// Matrix formula (reference for tests and for non-WNOA use):
///   Λ(τ) = Φ(τ,0) − Q(τ) Φ(Δt,τ)ᵀ Q(Δt)⁻¹ Φ(Δt,0),   Ψ(τ) = Q(τ) Φ(Δt,τ)ᵀ Q(Δt)⁻¹.
inline Mat12 psiMatrix(double tau, double dt, const Mat6& Q_c) {
  return covariance(tau, Q_c) * transition(dt - tau).transpose() * information(dt, Q_c.inverse());
}
inline Mat12 lambdaMatrix(double tau, double dt, const Mat6& Q_c) {
  return transition(tau) - psiMatrix(tau, dt, Q_c) * transition(dt);
}

/// The part of the interpolation that depends on the knots only, the same for every time in the
/// segment: ξ = Log(T_k⁻¹ T_{k+1}), J⁻¹ = J_r⁻¹(ξ), J⁻¹ϖ_{k+1}, and for the Jacobians A1 = J_l⁻¹(ξ) and
/// M = ∂(J_r⁻¹(ξ)ϖ_{k+1})/∂ξ. The GP projection factors of one segment share it (SegmentCache).
struct SegmentTerms {
  Vec6 xi = Vec6::Zero();
  Vec6 J_inv_w_k1 = Vec6::Zero();
  Mat6 J_inv = Mat6::Identity();
  Mat6 A1 = Mat6::Identity();
  Mat6 M = Mat6::Zero();
  bool with_jacobians = false;
};

inline SegmentTerms segmentTerms(const SE3& T_k, const SE3& T_k1, const Vec6& w_k1, bool with_jacobians,
                                 int series_order = kDefaultSeriesOrder) {
  SegmentTerms terms;
  terms.with_jacobians = with_jacobians;
  terms.xi = lie::se3::log(T_k.inverse() * T_k1);
  lie::se3::inverseJacobians(terms.xi, with_jacobians ? &terms.A1 : nullptr, &terms.J_inv);
  terms.J_inv_w_k1 = terms.J_inv * w_k1;
  if (with_jacobians) terms.M = dJrInvTimesVecDxi(terms.xi, w_k1, series_order);
  return terms;
}

/// Interpolated pose T(τ) = T_k Exp(ξ_τ), ξ_τ = Λ12 ϖ_k + Ψ11 ξ + Ψ12 J_r⁻¹(ξ) ϖ_{k+1},
/// ξ = Log(T_k⁻¹ T_{k+1}); and the chain rule from a right perturbation δ_τ of T(τ) to the knot
/// variables (right perturbations δ_k, δ_{k+1}; additive ϖ_k, ϖ_{k+1}):
///   ∂δ_τ/∂δ_k     = Ad(Exp(−ξ_τ)) − B·A1        ∂δ_τ/∂ϖ_k     = Λ12 J_τ
///   ∂δ_τ/∂δ_{k+1} = B·J⁻¹                        ∂δ_τ/∂ϖ_{k+1} = Ψ12 J_τ J⁻¹
/// with J_τ = J_r(ξ_τ), J⁻¹ = J_r⁻¹(ξ), A1 = J_l⁻¹(ξ), B = J_τ(Ψ11 I + Ψ12 M),
/// M = ∂(J_r⁻¹(ξ)ϖ_{k+1})/∂ξ (series, see dJrInvTimesVecDxi). docs/math/gp_backend.md §3.
class PoseInterpolator {
 public:
  /// Owns its segment terms (computed here).
  PoseInterpolator(const SE3& T_k, const Vec6& w_k, const SE3& T_k1, const Vec6& w_k1,
                   const InterpolationWeights& weights, bool with_jacobians = true,
                   int series_order = kDefaultSeriesOrder)
      : owned_(segmentTerms(T_k, T_k1, w_k1, with_jacobians, series_order)) {
    init(T_k, w_k, *owned_, weights, with_jacobians);
  }

  /// From the segment's knot-only terms (computed once per segment, see SegmentTerms). `segment` is
  /// referenced, not copied: it must outlive the interpolator. with_jacobians = false skips J_r(ξ_τ)
  /// where only the pose is wanted; Jacobians also need `segment` to have them.
  PoseInterpolator(const SE3& T_k, const Vec6& w_k, const SegmentTerms& segment, const InterpolationWeights& weights,
                   bool with_jacobians = true) {
    init(T_k, w_k, segment, weights, with_jacobians);
  }

  PoseInterpolator(const PoseInterpolator& other) { *this = other; }
  PoseInterpolator& operator=(const PoseInterpolator& other) {
    if (this == &other) return *this;
    owned_ = other.owned_;
    segment_ = owned_ ? &*owned_ : other.segment_;
    weights_ = other.weights_;
    has_jacobians_ = other.has_jacobians_;
    xi_tau_ = other.xi_tau_;
    T_k_tau_ = other.T_k_tau_;
    T_tau_ = other.T_tau_;
    J_tau_ = other.J_tau_;
    W_ = other.W_;
    return *this;
  }

  /// T(τ) (world from body at τ).
  const SE3& pose() const { return T_tau_; }
  /// ξ_τ = Log(T_k⁻¹ T(τ)).
  const Vec6& localPose() const { return xi_tau_; }
  /// ξ = Log(T_k⁻¹ T_{k+1}).
  const Vec6& knotTwist() const { return segment_->xi; }
  const InterpolationWeights& weights() const { return weights_; }
  /// Whether the Jacobian intermediates were computed (constructor argument with_jacobians).
  bool hasJacobians() const { return has_jacobians_; }

  /// Chain rule: given G = ∂f/∂δ_τ (R×6), returns ∂f/∂{δ_k, ϖ_k, δ_{k+1}, ϖ_{k+1}} (each R×6).
  /// Any output pointer may be null. Costs six R×6·6×6 products (requires with_jacobians).
  template <int R>
  void chain(const Eigen::Matrix<double, R, 6>& G, Eigen::Matrix<double, R, 6>* d_f_d_pose_k,
             Eigen::Matrix<double, R, 6>* d_f_d_vel_k, Eigen::Matrix<double, R, 6>* d_f_d_pose_k1,
             Eigen::Matrix<double, R, 6>* d_f_d_vel_k1) const {
    using RowBlock = Eigen::Matrix<double, R, 6>;
    const RowBlock GJ = G * J_tau_;
    const RowBlock GB = GJ * W_;
    if (d_f_d_pose_k != nullptr) {
      // G·Ad(Exp(ξ_τ)⁻¹) with Ad(T⁻¹) = [Rᵀ −Rᵀt^; 0 Rᵀ], without forming the 6×6 matrix.
      const Mat3 Rt = T_k_tau_.rotation().transpose();
      const Eigen::Matrix<double, R, 3> G1Rt = G.template leftCols<3>() * Rt;
      d_f_d_pose_k->template leftCols<3>() = G1Rt;
      d_f_d_pose_k->template rightCols<3>() =
          G.template rightCols<3>() * Rt - G1Rt * lie::so3::hat(T_k_tau_.translation());
      d_f_d_pose_k->noalias() -= GB * segment_->A1;
    }
    if (d_f_d_vel_k != nullptr) *d_f_d_vel_k = weights_.lambda12 * GJ;
    if (d_f_d_pose_k1 != nullptr) d_f_d_pose_k1->noalias() = GB * segment_->J_inv;
    if (d_f_d_vel_k1 != nullptr) d_f_d_vel_k1->noalias() = weights_.psi12 * (GJ * segment_->J_inv);
  }

  /// The four 6×6 Jacobians ∂δ_τ/∂(·).
  void jacobians(Mat6* d_tau_d_pose_k, Mat6* d_tau_d_vel_k, Mat6* d_tau_d_pose_k1,
                 Mat6* d_tau_d_vel_k1) const {
    chain<6>(Mat6::Identity(), d_tau_d_pose_k, d_tau_d_vel_k, d_tau_d_pose_k1, d_tau_d_vel_k1);
  }

  // Intermediate quantities, exposed for the velocity interpolation.
  const Mat6& rightJacobianTau() const { return J_tau_; }
  const Mat6& rightJacobianInverseXi() const { return segment_->J_inv; }
  const Mat6& leftJacobianInverseXi() const { return segment_->A1; }
  const Mat6& dJrInvTimesVelDxi() const { return segment_->M; }
  const Vec6& rightJacobianInverseTimesVelK1() const { return segment_->J_inv_w_k1; }

 private:
  void init(const SE3& T_k, const Vec6& w_k, const SegmentTerms& segment, const InterpolationWeights& weights,
            bool with_jacobians) {
    segment_ = &segment;
    weights_ = weights;
    has_jacobians_ = with_jacobians && segment.with_jacobians;
    xi_tau_ = weights.lambda12 * w_k + weights.psi11 * segment.xi + weights.psi12 * segment.J_inv_w_k1;
    if (has_jacobians_) {
      T_k_tau_ = lie::se3::expWithRightJacobian(xi_tau_, J_tau_);
      W_ = weights.psi12 * segment.M;
      W_.diagonal().array() += weights.psi11;
    } else {
      T_k_tau_ = lie::se3::exp(xi_tau_);
    }
    T_tau_ = T_k * T_k_tau_;
  }

  std::optional<SegmentTerms> owned_;  ///< the terms, when this interpolator computed them
  const SegmentTerms* segment_ = nullptr;
  InterpolationWeights weights_;
  bool has_jacobians_ = false;
  Vec6 xi_tau_;
  SE3 T_k_tau_;  // Exp(ξ_τ)
  SE3 T_tau_;
  Mat6 J_tau_ = Mat6::Identity();
  Mat6 W_ = Mat6::Zero();  // Ψ11 I + Ψ12 M
};

/// Jacobians of the interpolated body velocity ϖ(τ) (additive output) w.r.t. the knot variables.
struct VelocityJacobians {
  Mat6 d_w_d_pose_k;
  Mat6 d_w_d_vel_k;
  Mat6 d_w_d_pose_k1;
  Mat6 d_w_d_vel_k1;
};

/// Interpolated body velocity (reference/backend.md §3; docs/math/gp_backend.md §3.3):
///   v_τ = Λ22 ϖ_k + Ψ21 ξ + Ψ22 J_r⁻¹(ξ) ϖ_{k+1},   ϖ(τ) = J_r(ξ_τ) v_τ
///   N = ∂(J_r(ξ_τ) v)/∂ξ_τ (series),  B_ξ = N(Ψ11 I + Ψ12 M) + J_τ(Ψ21 I + Ψ22 M)
///   ∂ϖ(τ)/∂δ_k = −B_ξ A1                ∂ϖ(τ)/∂δ_{k+1} = B_ξ J⁻¹
///   ∂ϖ(τ)/∂ϖ_k = N Λ12 + J_τ Λ22        ∂ϖ(τ)/∂ϖ_{k+1} = (N Ψ12 + J_τ Ψ22) J⁻¹
/// Velocity Jacobians require `interp` built with Jacobians. They are less accurate than the pose Jacobians:
/// the series errors of N and M add up (see the tests for the measured figures).
inline Vec6 interpolateVelocity(const PoseInterpolator& interp, const Vec6& w_k,
                                VelocityJacobians* jacobians = nullptr,
                                int series_order = kDefaultSeriesOrder) {
  const InterpolationWeights& c = interp.weights();
  const Vec6 v =
      c.lambda22 * w_k + c.psi21 * interp.knotTwist() + c.psi22 * interp.rightJacobianInverseTimesVelK1();
  const Mat6 J_tau =
      interp.hasJacobians() ? interp.rightJacobianTau() : lie::se3::rightJacobian(interp.localPose());
  if (jacobians != nullptr && interp.hasJacobians()) {
    const Mat6 N = dJrTimesVecDxi(interp.localPose(), v, series_order);
    const Mat6& M = interp.dJrInvTimesVelDxi();
    const Mat6& J_inv = interp.rightJacobianInverseXi();
    Mat6 W1 = c.psi12 * M;
    W1.diagonal().array() += c.psi11;
    Mat6 W2 = c.psi22 * M;
    W2.diagonal().array() += c.psi21;
    const Mat6 B = N * W1 + J_tau * W2;
    jacobians->d_w_d_pose_k = -B * interp.leftJacobianInverseXi();
    jacobians->d_w_d_pose_k1 = B * J_inv;
    jacobians->d_w_d_vel_k = c.lambda12 * N + c.lambda22 * J_tau;
    jacobians->d_w_d_vel_k1 = (c.psi12 * N + c.psi22 * J_tau) * J_inv;
  } else if (jacobians != nullptr) {
    // Misuse (interpolator built without Jacobians): make it loud rather than silently stale.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    jacobians->d_w_d_pose_k.setConstant(nan);
    jacobians->d_w_d_vel_k.setConstant(nan);
    jacobians->d_w_d_pose_k1.setConstant(nan);
    jacobians->d_w_d_vel_k1.setConstant(nan);
  }
  return J_tau * v;
}

}  // namespace asynevo::gp
