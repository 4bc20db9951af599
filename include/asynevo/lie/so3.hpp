#pragma once
// SO(3) toolkit: hat/vee, Exp/Log (Log through the unit quaternion), left/right Jacobians and their
// inverses, with Taylor series below the small-angle threshold.
//
// Formulas: Barfoot, "State Estimation for Robotics" (SER) ch. 7; the coefficient series and the
// quaternion Log are restated and numerically checked in reference/backend.md §1. Derivation page:
// docs/math/gp_backend.md §1.
//
// Convention (DESIGN.md §3): right perturbation R·Exp(δφ). J_r(φ) = J_l(−φ).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace asynevo::lie {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat4 = Eigen::Matrix4d;
using Quat = Eigen::Quaterniond;

/// Below this squared angle (θ < 1e-2) every trigonometric coefficient switches to its Taylor series.
/// The truncation error of the series there is below 1e-17 (next terms are O(θ⁶)).
constexpr double kSmallAngleSquared = 1e-4;

namespace so3 {

/// a^ : the 3×3 skew-symmetric matrix with a^ b = a × b.
inline Mat3 hat(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(),  //
      a.z(), 0.0, -a.x(),   //
      -a.y(), a.x(), 0.0;
  return m;
}

/// Inverse of hat (reads the skew part; no check that m is skew).
inline Vec3 vee(const Mat3& m) { return Vec3(m(2, 1), m(0, 2), m(1, 0)); }

/// Trigonometric coefficients of the SO(3) closed forms at angle θ (θ = ‖φ‖ ≥ 0):
///   a = sinθ/θ, b = (1−cosθ)/θ², c = (θ−sinθ)/θ³, d = 1/θ² − (1+cosθ)/(2θ sinθ).
/// d is evaluated as 1/θ² − cot(θ/2)/(2θ), which stays finite at θ = π.
struct Coefficients {
  double a;
  double b;
  double c;
  double d;
};

inline Coefficients coefficients(double theta_sq) {
  Coefficients k{};
  if (theta_sq < kSmallAngleSquared) {
    const double t2 = theta_sq;
    const double t4 = t2 * t2;
    k.a = 1.0 - t2 / 6.0 + t4 / 120.0;
    k.b = 0.5 - t2 / 24.0 + t4 / 720.0;
    k.c = 1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0;
    k.d = 1.0 / 12.0 + t2 / 720.0 + t4 / 30240.0;
  } else {
    const double theta = std::sqrt(theta_sq);
    const double s = std::sin(theta);
    const double s_half = std::sin(0.5 * theta);
    k.a = s / theta;
    k.b = 2.0 * s_half * s_half / theta_sq;  // (1 − cosθ)/θ² without the cancellation
    k.c = (theta - s) / (theta_sq * theta);
    k.d = 1.0 / theta_sq - 1.0 / (2.0 * theta * std::tan(0.5 * theta));
  }
  return k;
}

/// Exp(φ) = I + a φ^ + b (φ^)².
inline Mat3 exp(const Vec3& phi) {
  const Coefficients k = coefficients(phi.squaredNorm());
  const Mat3 P = hat(phi);
  return Mat3::Identity() + k.a * P + k.b * P * P;
}

/// Exp(φ) as a unit quaternion: [cos(θ/2); sin(θ/2)/θ · φ].
inline Quat expQuaternion(const Vec3& phi) {
  const double theta_sq = phi.squaredNorm();
  double w = 0.0;
  double s = 0.0;  // sin(θ/2)/θ
  if (theta_sq < kSmallAngleSquared) {
    w = 1.0 - theta_sq / 8.0 + theta_sq * theta_sq / 384.0;
    s = 0.5 - theta_sq / 48.0 + theta_sq * theta_sq / 3840.0;
  } else {
    const double theta = std::sqrt(theta_sq);
    w = std::cos(0.5 * theta);
    s = std::sin(0.5 * theta) / theta;
  }
  Quat q(w, s * phi.x(), s * phi.y(), s * phi.z());
  q.normalize();  // the series is exact to round-off; this only removes the last ulp
  return q;
}

/// Log of a unit quaternion, θ ∈ [0, π] (the double cover is resolved by q ← −q when q_w < 0).
/// θ = 2·atan2(‖q_v‖, q_w); for ‖q_v‖ < 1e-8 the series φ ≈ (2/q_w − 2n²/(3q_w³)) q_v
/// (reference/backend.md §1). Well conditioned from 0 to π, unlike acos((tr R − 1)/2).
inline Vec3 log(const Quat& q_in) {
  Quat q = q_in;
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Vec3 qv = q.vec();
  const double n_sq = qv.squaredNorm();
  const double n = std::sqrt(n_sq);
  const double w = q.w();
  if (n < 1e-8) {
    return (2.0 / w - 2.0 * n_sq / (3.0 * w * w * w)) * qv;
  }
  const double theta = 2.0 * std::atan2(n, w);
  return (theta / n) * qv;
}

/// Log of a rotation matrix through its quaternion (Eigen's Shepperd conversion).
inline Vec3 log(const Mat3& R) {
  Quat q(R);
  q.normalize();
  return log(q);
}

/// J_l(φ) = I + b φ^ + c (φ^)².  Exp(φ + δ) ≈ Exp(J_l δ) Exp(φ).
inline Mat3 leftJacobian(const Vec3& phi) {
  const Coefficients k = coefficients(phi.squaredNorm());
  const Mat3 P = hat(phi);
  return Mat3::Identity() + k.b * P + k.c * P * P;
}

/// J_r(φ) = J_l(−φ) = I − b φ^ + c (φ^)².  Exp(φ + δ) ≈ Exp(φ) Exp(J_r δ).
inline Mat3 rightJacobian(const Vec3& phi) {
  const Coefficients k = coefficients(phi.squaredNorm());
  const Mat3 P = hat(phi);
  return Mat3::Identity() - k.b * P + k.c * P * P;
}

/// J_l⁻¹(φ) = I − ½ φ^ + d (φ^)² (singular at θ = 2π; fine for θ ≤ π).
inline Mat3 leftJacobianInverse(const Vec3& phi) {
  const Coefficients k = coefficients(phi.squaredNorm());
  const Mat3 P = hat(phi);
  return Mat3::Identity() - 0.5 * P + k.d * P * P;
}

/// J_r⁻¹(φ) = I + ½ φ^ + d (φ^)².  Log(Exp(φ) Exp(δ)) ≈ φ + J_r⁻¹ δ.
inline Mat3 rightJacobianInverse(const Vec3& phi) {
  const Coefficients k = coefficients(phi.squaredNorm());
  const Mat3 P = hat(phi);
  return Mat3::Identity() + 0.5 * P + k.d * P * P;
}

}  // namespace so3
}  // namespace asynevo::lie
