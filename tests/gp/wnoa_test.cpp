#include "asynevo/gp/wnoa.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "gp_test_util.hpp"

namespace asynevo::gp {
namespace {

using testing::KnotPair;
using testing::maxAbs;
using testing::numericJacobian;
using testing::randomKnotPair;
using testing::randomVec6;

Mat6 randomSpd(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Mat6 A;
  for (int i = 0; i < 36; ++i) A(i) = n(rng);
  return A * A.transpose() + 0.5 * Mat6::Identity();
}

TEST(Wnoa, CovarianceTimesInformationIsIdentity) {
  std::mt19937 rng(1);
  const Mat6 Q_c = randomSpd(rng);
  for (double dt : {0.005, 0.05, 0.3}) {
    const Mat12 Q = covariance(dt, Q_c);
    const Mat12 Q_inv = information(dt, Q_c.inverse());
    EXPECT_LT(maxAbs(Q * Q_inv - Mat12::Identity()), 1e-11) << dt;
  }
}

TEST(Wnoa, TransitionAndCovarianceComposeLikeTheSde) {
  // Φ(a)Φ(b) = Φ(a+b);  Q(a+b) = Φ(b) Q(a) Φ(b)ᵀ + Q(b).
  std::mt19937 rng(2);
  const Mat6 Q_c = randomSpd(rng);
  const double a = 0.03;
  const double b = 0.07;
  EXPECT_LT(maxAbs(transition(a) * transition(b) - transition(a + b)), 1e-16);
  const Mat12 lhs = covariance(a + b, Q_c);
  const Mat12 rhs = transition(b) * covariance(a, Q_c) * transition(b).transpose() + covariance(b, Q_c);
  EXPECT_LT(maxAbs(lhs - rhs), 1e-15 * maxAbs(lhs));
}

TEST(Wnoa, ClosedFormSquareRootInformation) {
  std::mt19937 rng(3);
  for (double dt : {0.005, 0.05, 0.3}) {
    // Full Q_c.
    const Mat6 Q_c = randomSpd(rng);
    const Mat12 L = sqrtInformation(dt, qcSqrtInformation(Q_c));
    const Mat12 Q_inv = information(dt, Q_c.inverse());
    EXPECT_LT(maxAbs(L.transpose() * L - Q_inv), 1e-13 * maxAbs(Q_inv)) << dt;
    // Diagonal Q_c: the per-axis form w_i = √12 Δt^{-3/2} q_i^{-1/2} e1_i − √3 Δt^{-1/2} q_i^{-1/2} e2_i,
    // w_{6+i} = Δt^{-1/2} q_i^{-1/2} e2_i (reference/backend.md §2).
    Vec6 q;
    q << 0.5, 0.5, 0.5, 0.1, 0.1, 0.1;
    const Mat12 L_diag = sqrtInformation(dt, qcSqrtInformation(Mat6(q.asDiagonal())));
    const Vec12 e = (Vec12() << randomVec6(rng, 1.0), randomVec6(rng, 1.0)).finished();
    const Vec12 w = L_diag * e;
    for (int i = 0; i < 6; ++i) {
      const double s = 1.0 / std::sqrt(q[i]);
      EXPECT_NEAR(w[i], std::sqrt(12.0) * std::pow(dt, -1.5) * s * e[i] - std::sqrt(3.0 / dt) * s * e[6 + i],
                  1e-12 * std::abs(w[i]) + 1e-12);
      EXPECT_NEAR(w[6 + i], s * e[6 + i] / std::sqrt(dt), 1e-13 * std::abs(w[6 + i]) + 1e-13);
    }
    const Mat12 Q_inv_diag = information(dt, Mat6(q.cwiseInverse().asDiagonal()));
    EXPECT_LT(maxAbs(L_diag.transpose() * L_diag - Q_inv_diag), 1e-15 * maxAbs(Q_inv_diag)) << dt;
  }
}

TEST(Wnoa, PriorErrorIsZeroOnConstantVelocity) {
  std::mt19937 rng(4);
  for (double speed : {0.1, 1.0, 5.0}) {
    const Vec6 w = randomVec6(rng, speed);
    const SE3 T_k = lie::se3::exp(randomVec6(rng, 2.0));
    const double dt = 0.2;
    const SE3 T_k1 = T_k * lie::se3::exp(dt * w);
    PriorJacobians J;
    const Vec12 e = priorError(T_k, w, T_k1, w, dt, &J);
    EXPECT_LT(e.norm(), 1e-14 * (1.0 + speed)) << speed;
    // The velocity Jacobians are exact everywhere; check them here against differences too.
    const Mat12x6 d_vel_k_num =
        numericJacobian<12>([&](const Vec6& d) { return priorError(T_k, Vec6(w + d), T_k1, w, dt); });
    const Mat12x6 d_vel_k1_num =
        numericJacobian<12>([&](const Vec6& d) { return priorError(T_k, w, T_k1, Vec6(w + d), dt); });
    EXPECT_LT(maxAbs(J.d_e_d_vel_k - d_vel_k_num), 1e-9);
    EXPECT_LT(maxAbs(J.d_e_d_vel_k1 - d_vel_k1_num), 1e-9);
  }
}

struct PriorJacobianErrors {
  double pose_k;
  double vel_k;
  double pose_k1;
  double vel_k1;
};

PriorJacobianErrors priorJacobianErrors(const KnotPair& p, int order) {
  PriorJacobians J;
  priorError(p.T_k, p.w_k, p.T_k1, p.w_k1, p.dt, &J, order);
  const auto f_pose_k = [&](const Vec6& d) {
    return priorError(p.T_k * lie::se3::exp(d), p.w_k, p.T_k1, p.w_k1, p.dt);
  };
  const auto f_pose_k1 = [&](const Vec6& d) {
    return priorError(p.T_k, p.w_k, p.T_k1 * lie::se3::exp(d), p.w_k1, p.dt);
  };
  const auto f_vel_k = [&](const Vec6& d) {
    return priorError(p.T_k, Vec6(p.w_k + d), p.T_k1, p.w_k1, p.dt);
  };
  const auto f_vel_k1 = [&](const Vec6& d) {
    return priorError(p.T_k, p.w_k, p.T_k1, Vec6(p.w_k1 + d), p.dt);
  };
  return {maxAbs(J.d_e_d_pose_k - numericJacobian<12>(f_pose_k)),
          maxAbs(J.d_e_d_vel_k - numericJacobian<12>(f_vel_k)),
          maxAbs(J.d_e_d_pose_k1 - numericJacobian<12>(f_pose_k1)),
          maxAbs(J.d_e_d_vel_k1 - numericJacobian<12>(f_vel_k1))};
}

TEST(Wnoa, PriorJacobiansMatchCentralDifferences) {
  // Tolerances: the second-order-M figures of reference/backend.md §2 (2e-10, 5e-7, 2e-4) scaled to
  // this setup (velocities up to 1.3‖ξ‖/Δt; the M series error grows like ‖ξ‖³‖ϖ_{k+1}‖); measured
  // maxima are printed. The velocity blocks are exact.
  struct Case {
    double xi_norm;
    double pose_tol;
  };
  std::mt19937 rng(5);
  for (const Case& c : {Case{0.01, 1e-9}, Case{0.1, 3e-6}, Case{0.3, 5e-4}}) {
    double worst_pose = 0.0;
    double worst_vel = 0.0;
    for (int trial = 0; trial < 5; ++trial) {
      const KnotPair p = randomKnotPair(rng, c.xi_norm);
      const PriorJacobianErrors err = priorJacobianErrors(p, kDefaultSeriesOrder);
      worst_pose = std::max({worst_pose, err.pose_k, err.pose_k1});
      worst_vel = std::max({worst_vel, err.vel_k, err.vel_k1});
      EXPECT_LT(err.pose_k, c.pose_tol) << "|xi| " << c.xi_norm;
      EXPECT_LT(err.pose_k1, c.pose_tol) << "|xi| " << c.xi_norm;
      EXPECT_LT(err.vel_k, 1e-8) << "|xi| " << c.xi_norm;
      EXPECT_LT(err.vel_k1, 1e-8) << "|xi| " << c.xi_norm;
    }
    std::printf("prior Jacobian max error |xi| = %.2f: pose %.1e, velocity %.1e\n", c.xi_norm, worst_pose,
                worst_vel);
  }
}

TEST(Wnoa, SeriesOrderControlsTheAccuracyOfM) {
  // M = ∂(J_r⁻¹(ξ)w)/∂ξ: the error against central differences falls with the series order.
  std::mt19937 rng(6);
  const Vec6 xi = randomVec6(rng, 0.3);
  const Vec6 w = randomVec6(rng, 3.0);
  const Mat6 M_num =
      numericJacobian<6>([&](const Vec6& d) { return Vec6(lie::se3::rightJacobianInverse(xi + d) * w); });
  const Mat6 N_num =
      numericJacobian<6>([&](const Vec6& d) { return Vec6(lie::se3::rightJacobian(xi + d) * w); });
  double previous_m = 1e300;
  double previous_n = 1e300;
  for (int order : {1, 2, 4, 6, 8}) {
    const double err_m = maxAbs(dJrInvTimesVecDxi(xi, w, order) - M_num);
    const double err_n = maxAbs(dJrTimesVecDxi(xi, w, order) - N_num);
    EXPECT_LT(err_m, previous_m) << "order " << order;
    EXPECT_LT(err_n, previous_n) << "order " << order;
    previous_m = err_m;
    previous_n = err_n;
  }
  EXPECT_LT(previous_m, 1e-8);
  EXPECT_LT(previous_n, 1e-8);
  // The explicit second-order formula of reference/backend.md §2.
  const Mat6 X = lie::se3::curlyHat(xi);
  const Mat6 M2 =
      -0.5 * lie::se3::curlyHat(w) - (lie::se3::curlyHat(X * w) + X * lie::se3::curlyHat(w)) / 12.0;
  EXPECT_LT(maxAbs(dJrInvTimesVecDxi(xi, w, 2) - M2), 1e-15);
  const Mat6 N2 = 0.5 * lie::se3::curlyHat(w) - (lie::se3::curlyHat(X * w) + X * lie::se3::curlyHat(w)) / 6.0;
  EXPECT_LT(maxAbs(dJrTimesVecDxi(xi, w, 2) - N2), 1e-15);
}

TEST(Wnoa, SecondOrderBeatsFirstOrderOnThePriorJacobians) {
  std::mt19937 rng(7);
  const KnotPair p = randomKnotPair(rng, 0.1);
  const PriorJacobianErrors first = priorJacobianErrors(p, 1);
  const PriorJacobianErrors second = priorJacobianErrors(p, 2);
  EXPECT_LT(second.pose_k, 0.1 * first.pose_k);
  EXPECT_LT(second.pose_k1, 0.1 * first.pose_k1);
}

}  // namespace
}  // namespace asynevo::gp
