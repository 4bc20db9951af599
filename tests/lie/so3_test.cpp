#include "asynevo/lie/so3.hpp"

#include <gtest/gtest.h>

#include <random>

#include "lie_test_util.hpp"

namespace asynevo::lie {
namespace {

using testing::angleSweep;
using testing::powerSeries;
using testing::randomUnit;
using testing::safeStep;

TEST(So3, HatVeeRoundTripAndCrossProduct) {
  const Vec3 a(0.3, -1.2, 2.5);
  const Vec3 b(-0.7, 0.1, 0.4);
  EXPECT_LT((so3::vee(so3::hat(a)) - a).norm(), 1e-15);
  EXPECT_LT((so3::hat(a) * b - a.cross(b)).norm(), 1e-15);
  EXPECT_LT((so3::hat(a) + so3::hat(a).transpose()).norm(), 1e-15);
}

TEST(So3, CoefficientSeriesMatchClosedFormAtTheThreshold) {
  // Just below and just above θ = 1e-2 the two branches must agree (continuity of the switch).
  const so3::Coefficients below = so3::coefficients(kSmallAngleSquared * (1.0 - 1e-12));
  const so3::Coefficients above = so3::coefficients(kSmallAngleSquared * (1.0 + 1e-12));
  EXPECT_NEAR(below.a, above.a, 1e-14);
  EXPECT_NEAR(below.b, above.b, 1e-15);
  EXPECT_NEAR(below.c, above.c, 1e-11);  // closed form of c cancels: (θ − sinθ)/θ³
  EXPECT_NEAR(below.d, above.d, 1e-11);
}

TEST(So3, ExpMatchesAngleAxisAndQuaternion) {
  std::mt19937 rng(1);
  for (double theta : angleSweep()) {
    const Vec3 axis = randomUnit(rng);
    const Vec3 phi = theta * axis;
    const Mat3 R = so3::exp(phi);
    const Mat3 R_ref = Eigen::AngleAxisd(theta, axis).toRotationMatrix();
    EXPECT_LT((R - R_ref).norm(), 1e-14) << "theta " << theta;
    EXPECT_LT((so3::expQuaternion(phi).toRotationMatrix() - R_ref).norm(), 1e-14) << "theta " << theta;
    EXPECT_LT((R.transpose() * R - Mat3::Identity()).norm(), 1e-14);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
  }
}

TEST(So3, LogInvertsExp) {
  std::mt19937 rng(2);
  for (double theta : angleSweep()) {
    const Vec3 phi = theta * randomUnit(rng);
    const Vec3 from_matrix = so3::log(so3::exp(phi));
    const Vec3 from_quaternion = so3::log(so3::expQuaternion(phi));
    // Relative to θ for small angles; near π the quaternion route keeps ~1e-10 absolute.
    const double tol = std::max(1e-15, 1e-14 * theta) + (theta > 3.1 ? 1e-9 : 0.0);
    EXPECT_LT((from_matrix - phi).norm(), tol) << "theta " << theta;
    EXPECT_LT((from_quaternion - phi).norm(), tol) << "theta " << theta;
  }
}

TEST(So3, LogResolvesTheQuaternionDoubleCover) {
  const Vec3 phi(0.2, -0.4, 0.1);
  Quat q = so3::expQuaternion(phi);
  q.coeffs() = -q.coeffs();
  EXPECT_LT((so3::log(q) - phi).norm(), 1e-15);
  EXPECT_LT(so3::log(Quat::Identity()).norm(), 1e-300);
}

TEST(So3, LeftJacobianMatchesPowerSeries) {
  std::mt19937 rng(3);
  for (double theta : angleSweep()) {
    const Vec3 phi = theta * randomUnit(rng);
    const Mat3 series = powerSeries<3>(so3::hat(phi), 1);  // Σ (φ^)ⁿ/(n+1)!
    EXPECT_LT((so3::leftJacobian(phi) - series).norm(), 1e-14) << "theta " << theta;
    EXPECT_LT((so3::rightJacobian(phi) - powerSeries<3>(so3::hat(-phi), 1)).norm(), 1e-14);
  }
}

TEST(So3, JacobianIdentities) {
  std::mt19937 rng(4);
  for (double theta : angleSweep()) {
    const Vec3 phi = theta * randomUnit(rng);
    const Mat3 Jl = so3::leftJacobian(phi);
    const Mat3 Jr = so3::rightJacobian(phi);
    EXPECT_LT((Jl * so3::leftJacobianInverse(phi) - Mat3::Identity()).norm(), 1e-12) << theta;
    EXPECT_LT((Jr * so3::rightJacobianInverse(phi) - Mat3::Identity()).norm(), 1e-12) << theta;
    EXPECT_LT((Jl - so3::exp(phi) * Jr).norm(), 1e-14) << theta;
    EXPECT_LT((Jr * phi - phi).norm(), 1e-15);
    EXPECT_LT((so3::rightJacobianInverse(phi) * phi - phi).norm(), 1e-14);
  }
}

TEST(So3, RightJacobiansMatchNumericalDerivatives) {
  std::mt19937 rng(5);
  for (double theta : angleSweep()) {
    const Vec3 phi = theta * randomUnit(rng);
    const double h = safeStep(theta);
    const Mat3 R = so3::exp(phi);
    Mat3 Jr_num;
    Mat3 Jr_inv_num;
    for (int i = 0; i < 3; ++i) {
      const Vec3 e = Vec3::Unit(i) * h;
      // Exp(φ + δ) ≈ Exp(φ) Exp(J_r δ)
      Jr_num.col(i) = (so3::log(Mat3(R.transpose() * so3::exp(phi + e))) -
                       so3::log(Mat3(R.transpose() * so3::exp(phi - e)))) /
                      (2 * h);
      // Log(Exp(φ) Exp(δ)) ≈ φ + J_r⁻¹ δ
      Jr_inv_num.col(i) = (so3::log(Mat3(R * so3::exp(e))) - so3::log(Mat3(R * so3::exp(-e)))) / (2 * h);
    }
    EXPECT_LT((Jr_num - so3::rightJacobian(phi)).cwiseAbs().maxCoeff(), 1e-8) << "theta " << theta;
    EXPECT_LT((Jr_inv_num - so3::rightJacobianInverse(phi)).cwiseAbs().maxCoeff(), 1e-8) << "theta " << theta;
  }
}

}  // namespace
}  // namespace asynevo::lie
