#include "asynevo/lie/se3.hpp"

#include <gtest/gtest.h>

#include <random>

#include "lie_test_util.hpp"

namespace asynevo::lie {
namespace {

using testing::angleSweep;
using testing::powerSeries;
using testing::randomTwist;
using testing::safeStep;

double maxAbs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

TEST(Se3, HatVeeAndCurlyHat) {
  std::mt19937 rng(10);
  const Vec6 xi = randomTwist(rng, 0.7);
  const Vec6 a = randomTwist(rng, 1.3);
  EXPECT_LT((se3::vee(se3::hat(xi)) - xi).norm(), 1e-15);
  // ξ⋏ a = −a⋏ ξ, and ξ⋏ ξ = 0.
  EXPECT_LT((se3::curlyHat(xi) * a + se3::curlyHat(a) * xi).norm(), 1e-15);
  EXPECT_LT((se3::curlyHat(xi) * xi).norm(), 1e-15);
  // ad is the matrix commutator: (ξ⋏a)^ = ξ^a^ − a^ξ^.
  const Mat4 commutator = se3::hat(xi) * se3::hat(a) - se3::hat(a) * se3::hat(xi);
  EXPECT_LT((se3::hat(se3::curlyHat(xi) * a) - commutator).norm(), 1e-14);
}

TEST(Se3, GroupOperations) {
  std::mt19937 rng(11);
  const SE3 A = se3::exp(randomTwist(rng, 2.0));
  const SE3 B = se3::exp(randomTwist(rng, 0.4));
  const Vec3 p(0.3, -0.2, 1.5);
  EXPECT_LT(((A * B).matrix() - A.matrix() * B.matrix()).norm(), 1e-14);
  EXPECT_LT(((A.inverse() * A).matrix() - Mat4::Identity()).norm(), 1e-14);
  EXPECT_LT((A * p - (A.rotation() * p + A.translation())).norm(), 1e-15);
  EXPECT_LT((SE3(A.quaternion(), A.translation()).matrix() - A.matrix()).norm(), 1e-14);
  EXPECT_LT((se3::adjointInverse(A) - se3::adjoint(A.inverse())).norm(), 1e-14);
  // T Exp(ξ) T⁻¹ = Exp(Ad(T) ξ)
  const Vec6 xi = randomTwist(rng, 0.9);
  EXPECT_LT(((A * se3::exp(xi) * A.inverse()).matrix() - se3::exp(se3::adjoint(A) * xi).matrix()).norm(),
            1e-13);
}

TEST(Se3, ExpMatchesMatrixExponentialAndLogInvertsIt) {
  std::mt19937 rng(12);
  for (double theta : angleSweep()) {
    const Vec6 xi = randomTwist(rng, theta);
    const SE3 T = se3::exp(xi);
    EXPECT_LT((T.matrix() - powerSeries<4>(se3::hat(xi), 0)).norm(), 1e-13) << "theta " << theta;
    const double tol = 1e-14 + (theta > 3.1 ? 1e-9 : 0.0);
    EXPECT_LT((se3::log(T) - xi).norm(), tol) << "theta " << theta;
  }
}

TEST(Se3, AdjointIsExpOfCurlyHat) {
  std::mt19937 rng(13);
  for (double theta : angleSweep()) {
    const Vec6 xi = randomTwist(rng, theta);
    EXPECT_LT((se3::adjoint(se3::exp(xi)) - powerSeries<6>(se3::curlyHat(xi), 0)).norm(), 1e-13)
        << "theta " << theta;
  }
}

TEST(Se3, LeftJacobianMatchesPowerSeries) {
  std::mt19937 rng(14);
  for (double theta : angleSweep()) {
    const Vec6 xi = randomTwist(rng, theta);
    // J_l(ξ) = Σ (ξ⋏)ⁿ/(n+1)!  — checks Q_l and its series on both sides of its threshold.
    EXPECT_LT(maxAbs(se3::leftJacobian(xi) - powerSeries<6>(se3::curlyHat(xi), 1)), 1e-14)
        << "theta " << theta;
    EXPECT_LT(maxAbs(se3::rightJacobian(xi) - powerSeries<6>(se3::curlyHat(-xi), 1)), 1e-14)
        << "theta " << theta;
  }
}

TEST(Se3, QLeftSeriesMatchesClosedFormAtItsThreshold) {
  std::mt19937 rng(15);
  const Vec6 dir = randomTwist(rng, 1.0);
  for (double theta : {0.1 * (1 - 1e-9), 0.1 * (1 + 1e-9)}) {
    Vec6 xi = dir;
    xi.tail<3>() *= theta;
    EXPECT_LT(maxAbs(se3::qLeft(xi) - powerSeries<6>(se3::curlyHat(xi), 1).topRightCorner<3, 3>()), 1e-14);
  }
}

TEST(Se3, JacobianIdentities) {
  std::mt19937 rng(16);
  for (double theta : angleSweep()) {
    const Vec6 xi = randomTwist(rng, theta);
    const Mat6 Jl = se3::leftJacobian(xi);
    const Mat6 Jr = se3::rightJacobian(xi);
    const Mat6 Jl_inv = se3::leftJacobianInverse(xi);
    const Mat6 Jr_inv = se3::rightJacobianInverse(xi);
    EXPECT_LT(maxAbs(Jl * Jl_inv - Mat6::Identity()), 1e-12) << theta;
    EXPECT_LT(maxAbs(Jr * Jr_inv - Mat6::Identity()), 1e-12) << theta;
    EXPECT_LT(maxAbs(Jl - se3::adjoint(se3::exp(xi)) * Jr), 1e-14) << theta;
    EXPECT_LT((Jr * xi - xi).norm(), 1e-14) << theta;
    EXPECT_LT((Jr_inv * xi - xi).norm(), 1e-13) << theta;
  }
}

TEST(Se3, CombinedInverseJacobiansMatchTheSeparateOnes) {
  std::mt19937 rng(20);
  for (double theta : angleSweep()) {
    const Vec6 xi = randomTwist(rng, theta);
    Mat6 Jl_inv;
    Mat6 Jr_inv;
    se3::inverseJacobians(xi, &Jl_inv, &Jr_inv);
    EXPECT_LT(maxAbs(Jl_inv - se3::leftJacobianInverse(xi)), 1e-14) << theta;
    EXPECT_LT(maxAbs(Jr_inv - se3::rightJacobianInverse(xi)), 1e-14) << theta;
  }
}

TEST(Se3, ExpWithRightJacobianGivesTheSeparateResultsBitForBit) {
  std::mt19937 rng(21);
  for (double theta : angleSweep()) {
    const Vec6 xi = randomTwist(rng, theta);
    Mat6 J_r;
    const SE3 T = se3::expWithRightJacobian(xi, J_r);
    const SE3 T_ref = se3::exp(xi);
    const Mat6 J_ref = se3::rightJacobian(xi);
    EXPECT_TRUE(T.rotation() == T_ref.rotation()) << theta;
    EXPECT_TRUE(T.translation() == T_ref.translation()) << theta;
    EXPECT_TRUE(J_r == J_ref) << theta << "\n" << J_r - J_ref;
  }
}

TEST(Se3, RightJacobianInverseMatchesBernoulliSeriesForModerateAngles) {
  std::mt19937 rng(17);
  for (double theta : {1e-9, 1e-5, 3e-3, 2e-2, 0.5}) {
    const Vec6 xi = randomTwist(rng, theta);
    const Mat6 X = se3::curlyHat(xi);
    const Mat6 X2 = X * X;
    const Mat6 X4 = X2 * X2;
    // J_r⁻¹(ξ) = Σ Bₙ/n! (−ξ⋏)ⁿ = I + ½ξ⋏ + (1/12)(ξ⋏)² − (1/720)(ξ⋏)⁴ + (1/30240)(ξ⋏)⁶
    //            − (1/1209600)(ξ⋏)⁸ + (1/47900160)(ξ⋏)¹⁰ − …  (Bernoulli numbers)
    const Mat6 X8 = X4 * X4;
    const Mat6 series = Mat6::Identity() + 0.5 * X + X2 / 12.0 - X4 / 720.0 + X4 * X2 / 30240.0 -
                        X8 / 1209600.0 + X8 * X2 / 47900160.0;
    // The truncation error is O(θ¹²) and only visible at θ = 0.5.
    EXPECT_LT(maxAbs(se3::rightJacobianInverse(xi) - series), theta < 0.1 ? 1e-15 : 1e-11) << theta;
  }
}

TEST(Se3, RightJacobiansMatchNumericalDerivatives) {
  std::mt19937 rng(18);
  for (double theta : angleSweep()) {
    const Vec6 xi = randomTwist(rng, theta);
    const SE3 T = se3::exp(xi);
    const double h = safeStep(theta);
    Mat6 Jr_num;
    Mat6 Jr_inv_num;
    for (int i = 0; i < 6; ++i) {
      const Vec6 e = Vec6::Unit(i) * h;
      // Exp(ξ + δ) ≈ Exp(ξ) Exp(J_r δ)
      Jr_num.col(i) =
          (se3::log(T.inverse() * se3::exp(xi + e)) - se3::log(T.inverse() * se3::exp(xi - e))) / (2 * h);
      // Log(Exp(ξ) Exp(δ)) ≈ ξ + J_r⁻¹ δ
      Jr_inv_num.col(i) = (se3::log(T * se3::exp(e)) - se3::log(T * se3::exp(-e))) / (2 * h);
    }
    EXPECT_LT(maxAbs(Jr_num - se3::rightJacobian(xi)), 1e-8) << "theta " << theta;
    EXPECT_LT(maxAbs(Jr_inv_num - se3::rightJacobianInverse(xi)), 1e-8) << "theta " << theta;
  }
}

TEST(Se3, BoxMinusInvertsTheRetraction) {
  std::mt19937 rng(19);
  const SE3 T = se3::exp(randomTwist(rng, 2.5));
  for (double theta : angleSweep()) {
    const Vec6 d = randomTwist(rng, theta);
    EXPECT_LT((se3::boxMinus(T * se3::exp(d), T) - d).norm(), 1e-13 + (theta > 3.1 ? 1e-9 : 0.0)) << theta;
  }
}

}  // namespace
}  // namespace asynevo::lie
