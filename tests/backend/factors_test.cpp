#include <ceres/loss_function.h>
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "asynevo/backend/factors/fixed_pose_projection_factor.hpp"
#include "asynevo/backend/factors/gp_projection_factor.hpp"
#include "asynevo/backend/factors/linear_prior_factor.hpp"
#include "asynevo/backend/factors/pose_block.hpp"
#include "asynevo/backend/factors/se3_manifold.hpp"
#include "asynevo/backend/factors/state_prior_factor.hpp"
#include "asynevo/backend/factors/wnoa_prior_factor.hpp"
#include "testing/jacobian_check.hpp"

namespace asynevo::backend {
namespace {

using lie::SE3;
using lie::Vec6;
using testing::checkJacobians;

Vec6 randomVec6(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec6 v;
  for (int i = 0; i < 6; ++i) v[i] = n(rng);
  return scale * v / v.norm();
}

std::vector<double> poseBlock(const SE3& T) {
  std::vector<double> x(7);
  poseToBlock(T, x.data());
  return x;
}

std::vector<double> vecBlock(const Vec6& v) { return {v.data(), v.data() + 6}; }

TEST(Se3Manifold, PlusIsRightMultiplicationByExpAndMinusInvertsIt) {
  std::mt19937 rng(1);
  const SE3Manifold manifold;
  const SE3 T = lie::se3::exp(randomVec6(rng, 2.0));
  const std::vector<double> x = poseBlock(T);
  for (double size : {1e-9, 1e-3, 0.5, 2.5}) {
    const Vec6 delta = randomVec6(rng, size);
    std::array<double, 7> y{};
    ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), y.data()));
    const SE3 expected = T * lie::se3::exp(delta);
    EXPECT_LT((poseFromBlock(y.data()).matrix() - expected.matrix()).norm(), 1e-14) << size;
    EXPECT_NEAR(Eigen::Map<const Eigen::Vector4d>(y.data() + 3).norm(), 1.0, 1e-15);
    Vec6 back;
    ASSERT_TRUE(manifold.Minus(y.data(), x.data(), back.data()));
    EXPECT_LT((back - delta).norm(), 1e-13) << size;
  }
  // Minus is insensitive to the quaternion double cover.
  std::vector<double> x_neg = x;
  for (int i = 3; i < 7; ++i) x_neg[i] = -x_neg[i];
  Vec6 zero;
  ASSERT_TRUE(manifold.Minus(x_neg.data(), x.data(), zero.data()));
  EXPECT_LT(zero.norm(), 1e-15);
  // Tangent-Jacobian convention.
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus_jacobian;
  Eigen::Matrix<double, 6, 7, Eigen::RowMajor> minus_jacobian;
  manifold.PlusJacobian(x.data(), plus_jacobian.data());
  manifold.MinusJacobian(x.data(), minus_jacobian.data());
  EXPECT_EQ((minus_jacobian * plus_jacobian - lie::Mat6::Identity()).norm(), 0.0);
}

struct KnotPair {
  SE3 T_k, T_k1;
  Vec6 w_k, w_k1;
  double dt;
};

KnotPair randomKnotPair(std::mt19937& rng, double xi_norm, double dt = 0.1) {
  KnotPair p;
  p.dt = dt;
  p.T_k = lie::se3::exp(randomVec6(rng, 1.0));
  const Vec6 xi = randomVec6(rng, xi_norm);
  p.T_k1 = p.T_k * lie::se3::exp(xi);
  p.w_k = xi / dt + randomVec6(rng, 0.3 * xi_norm / dt);
  p.w_k1 = xi / dt + randomVec6(rng, 0.3 * xi_norm / dt);
  return p;
}

TEST(WnoaPriorFactor, WhitenedResidualAndJacobians) {
  std::mt19937 rng(2);
  const SE3Manifold se3;
  Vec6 q;
  q << 0.5, 0.5, 0.5, 0.2, 0.2, 0.2;
  const lie::Mat6 Q_c = q.asDiagonal();
  for (double xi_norm : {0.01, 0.1, 0.3}) {
    const KnotPair p = randomKnotPair(rng, xi_norm);
    const WnoaPriorFactor factor(p.dt, Q_c);
    const std::vector<std::vector<double>> values = {poseBlock(p.T_k), vecBlock(p.w_k), poseBlock(p.T_k1),
                                                     vecBlock(p.w_k1)};
    // ‖r‖² = eᵀ Q(Δt)⁻¹ e.
    gp::Vec12 r;
    const double* params[] = {values[0].data(), values[1].data(), values[2].data(), values[3].data()};
    ASSERT_TRUE(factor.Evaluate(params, r.data(), nullptr));
    const gp::Vec12 e = gp::priorError(p.T_k, p.w_k, p.T_k1, p.w_k1, p.dt);
    const double cost = e.dot(gp::information(p.dt, Q_c.inverse()) * e);
    EXPECT_NEAR(r.squaredNorm(), cost, 1e-12 * cost);

    const auto result = checkJacobians(factor, values, {&se3, nullptr, &se3, nullptr});
    ASSERT_TRUE(result.evaluated);
    // Relative to the whitening scale (entries of L reach √12 Δt^{-3/2} q^{-1/2} ≈ 150); the series
    // error of M (prior Jacobian table, reference/backend.md §2) dominates at ‖ξ‖ = 0.3.
    const double tol = xi_norm <= 0.1 ? 1e-6 : 1e-3;
    for (size_t i = 0; i < 4; ++i) {
      EXPECT_LT(result.max_abs_error[i], tol * result.max_abs_numeric[i]) << "|xi| " << xi_norm << "\n"
                                                                          << result.report();
    }
    std::printf("WnoaPriorFactor |xi| = %.2f:\n%s", xi_norm, result.report().c_str());
  }
}

TEST(WnoaPriorFactor, ZeroOnConstantVelocity) {
  std::mt19937 rng(3);
  const Vec6 w = randomVec6(rng, 2.0);
  const SE3 T_k = lie::se3::exp(randomVec6(rng, 1.0));
  const SE3 T_k1 = T_k * lie::se3::exp(0.05 * w);
  const WnoaPriorFactor factor(int64_t{1'000'000'000}, int64_t{1'050'000'000}, lie::Mat6::Identity());
  EXPECT_DOUBLE_EQ(factor.dt(), 0.05);
  const std::vector<double> a = poseBlock(T_k), b = vecBlock(w), c = poseBlock(T_k1);
  const double* params[] = {a.data(), b.data(), c.data(), b.data()};
  gp::Vec12 r;
  ASSERT_TRUE(factor.Evaluate(params, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-11);
}

/// The factor's whitened residual and tangent Jacobian (12×24: δT_k, δϖ_k, δT_{k+1}, δϖ_{k+1}).
std::pair<gp::Vec12, Eigen::Matrix<double, 12, 24>> evaluateTangent(
    const WnoaPriorFactor& factor, const std::vector<std::vector<double>>& values) {
  const double* params[] = {values[0].data(), values[1].data(), values[2].data(), values[3].data()};
  Eigen::Matrix<double, 12, 7, Eigen::RowMajor> J0, J2;
  Eigen::Matrix<double, 12, 6, Eigen::RowMajor> J1, J3;
  double* jacobians[] = {J0.data(), J1.data(), J2.data(), J3.data()};
  gp::Vec12 r;
  EXPECT_TRUE(factor.Evaluate(params, r.data(), jacobians));
  Eigen::Matrix<double, 12, 24> J;
  J << J0.leftCols<6>(), J1, J2.leftCols<6>(), J3;
  return {r, J};
}

TEST(WnoaPriorFactor, ScaleFreeJacobianHasNoComponentAlongTheScaleOnly) {
  std::mt19937 rng(12);
  Vec6 q;
  q << 0.5, 0.5, 0.5, 0.2, 0.2, 0.2;
  const lie::Mat6 Q_c = q.asDiagonal();
  for (double xi_norm : {0.05, 0.3}) {
    const KnotPair p = randomKnotPair(rng, xi_norm);
    const std::vector<std::vector<double>> values = {poseBlock(p.T_k), vecBlock(p.w_k), poseBlock(p.T_k1),
                                                     vecBlock(p.w_k1)};
    const auto [r, J] = evaluateTangent(WnoaPriorFactor(p.dt, Q_c), values);
    const auto [r_free, J_free] =
        evaluateTangent(WnoaPriorFactor(p.dt, Q_c, gp::kDefaultSeriesOrder, true), values);
    EXPECT_EQ((r - r_free).norm(), 0.0) << "the residual is unchanged";

    // u is the scale direction: scaling the map by (1 ± ε) about T_k's position, applied to the values
    // themselves, changes the residual by ±ε J u (central difference).
    const Eigen::Matrix<double, 24, 1> u = WnoaPriorFactor::scaleDirection(p.T_k, p.w_k, p.T_k1, p.w_k1);
    const double eps = 1e-6;
    gp::Vec12 r_scaled[2];
    for (int side = 0; side < 2; ++side) {
      const double s = 1.0 + (side == 0 ? eps : -eps);
      const SE3 T_k1(p.T_k1.rotation(),
                     p.T_k.translation() + s * (p.T_k1.translation() - p.T_k.translation()));
      Vec6 w_k = p.w_k, w_k1 = p.w_k1;
      w_k.head<3>() *= s;
      w_k1.head<3>() *= s;
      const std::vector<std::vector<double>> scaled = {poseBlock(p.T_k), vecBlock(w_k), poseBlock(T_k1),
                                                       vecBlock(w_k1)};
      const double* scaled_params[] = {scaled[0].data(), scaled[1].data(), scaled[2].data(),
                                       scaled[3].data()};
      ASSERT_TRUE(WnoaPriorFactor(p.dt, Q_c).Evaluate(scaled_params, r_scaled[side].data(), nullptr));
    }
    const gp::Vec12 numeric = (r_scaled[0] - r_scaled[1]) / (2 * eps);
    // The translational entries of e are homogeneous of degree 1 in the scale, the rotational ones of
    // degree 0: the plain prior pulls on the scale with J u = L [e_ρ; 0; e_v; 0].
    gp::Vec12 e_translational = gp::priorError(p.T_k, p.w_k, p.T_k1, p.w_k1, p.dt);
    e_translational.segment<3>(3).setZero();
    e_translational.segment<3>(9).setZero();
    const gp::Vec12 pull = WnoaPriorFactor(p.dt, Q_c).sqrtInformation() * e_translational;
    EXPECT_GT(pull.norm(), 0.1 * r.norm());
    // Tolerance as in WhitenedResidualAndJacobians: the series of M limits the analytic Jacobian.
    const double tol = xi_norm <= 0.1 ? 1e-5 : 1e-3;
    EXPECT_LT((J * u - pull).norm(), tol * pull.norm());
    EXPECT_LT((numeric - J * u).norm(), tol * (J * u).norm());

    // The projected Jacobian: no component along u, unchanged on the rigid gauge directions (where the
    // plain one is zero too) and on every direction orthogonal to w, a rank-one change otherwise.
    EXPECT_LT((J_free * u).norm(), 1e-9 * (J * u).norm());
    const Eigen::Matrix<double, 24, 6> G = WnoaPriorFactor::gaugeDirections(p.T_k, p.T_k1);
    EXPECT_LT((J * G).norm(), 1e-8 * J.norm());
    EXPECT_LT((J_free * G).norm(), 1e-8 * J.norm());
    const Eigen::Matrix<double, 24, 1> w = u - G * (G.transpose() * G).ldlt().solve(G.transpose() * u);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::Matrix<double, 24, 1> d = Eigen::Matrix<double, 24, 1>::Random();
      d -= w * (w.dot(d) / w.squaredNorm());
      EXPECT_LT((J_free * d - J * d).norm(), 1e-9 * J.norm() * d.norm());
    }
    Eigen::JacobiSVD<Eigen::Matrix<double, 12, 24>> svd(J_free - J);
    EXPECT_LT(svd.singularValues()(1), 1e-9 * svd.singularValues()(0)) << "a rank-one change";
  }
}

TEST(GpProjectionFactor, ResidualIsZeroAtTheInterpolatedTruthAndJacobiansMatch) {
  std::mt19937 rng(4);
  const SE3Manifold se3;
  for (double xi_norm : {0.01, 0.1, 0.3}) {
    double worst_relative = 0.0;
    for (double s : {0.0, 0.4, 1.0}) {
      const KnotPair p = randomKnotPair(rng, xi_norm);
      const gp::InterpolationWeights weights = gp::interpolationWeights(s * p.dt, p.dt);
      const gp::PoseInterpolator interp(p.T_k, p.w_k, p.T_k1, p.w_k1, weights, false);
      const Eigen::Vector3d p_c(0.3, -0.2, 3.0);
      const Eigen::Vector3d p_w = interp.pose() * p_c;
      const Eigen::Vector2d z = p_c.head<2>() / p_c.z();
      const double sigma = 1.0 / 300.0;
      const GpProjectionFactor factor(z, weights, sigma);
      const std::vector<std::vector<double>> values = {poseBlock(p.T_k),
                                                       vecBlock(p.w_k),
                                                       poseBlock(p.T_k1),
                                                       vecBlock(p.w_k1),
                                                       {p_w.x(), p_w.y(), p_w.z()}};
      const double* params[] = {values[0].data(), values[1].data(), values[2].data(), values[3].data(),
                                values[4].data()};
      Eigen::Vector2d r;
      ASSERT_TRUE(factor.Evaluate(params, r.data(), nullptr));
      EXPECT_LT(r.norm(), 1e-9);

      // Off the truth too (the landmark moved), so the residual is not zero.
      std::vector<std::vector<double>> off = values;
      off[4] = {p_w.x() + 0.1, p_w.y() - 0.05, p_w.z() + 0.2};
      const std::vector<std::vector<double>>* cases[] = {&values, &off};
      for (const auto* v : cases) {
        const auto result = checkJacobians(factor, *v, {&se3, nullptr, &se3, nullptr, nullptr});
        ASSERT_TRUE(result.evaluated);
        for (size_t i = 0; i < 5; ++i) {
          // 1e-6 relative at ‖ξ‖ ≤ 0.1 (issue 5); at 0.3 the second-order M error (≈1e-5 relative).
          const double tol = xi_norm <= 0.1 ? 1e-6 : 5e-5;
          const double scale = std::max(1.0, result.max_abs_numeric[i]);
          EXPECT_LT(result.max_abs_error[i], tol * scale) << "|xi| " << xi_norm << " s " << s << "\n"
                                                          << result.report();
          worst_relative = std::max(worst_relative, result.max_abs_error[i] / scale);
        }
      }
    }
    std::printf("GpProjectionFactor |xi| = %.2f: max Jacobian error %.1e relative to max(1, |J|)\n", xi_norm,
                worst_relative);
  }
}

TEST(GpProjectionFactor, ASharedSegmentCacheGivesBitIdenticalResultsAndComputesOncePerEvaluationPoint) {
  std::mt19937 rng(11);
  const KnotPair p = randomKnotPair(rng, 0.2);
  auto cache = std::make_shared<SegmentCache>();
  std::vector<std::vector<double>> values = {poseBlock(p.T_k), vecBlock(p.w_k), poseBlock(p.T_k1), vecBlock(p.w_k1),
                                             {0.2, -0.1, 3.0}};
  auto evaluate = [&](const GpProjectionFactor& f, Eigen::Vector2d& r, std::array<std::vector<double>, 5>& J) {
    const double* params[] = {values[0].data(), values[1].data(), values[2].data(), values[3].data(),
                              values[4].data()};
    const int sizes[] = {7, 6, 7, 6, 3};
    double* jac[5];
    for (int i = 0; i < 5; ++i) {
      J[static_cast<std::size_t>(i)].assign(static_cast<std::size_t>(2 * sizes[i]), 0.0);
      jac[i] = J[static_cast<std::size_t>(i)].data();
    }
    return f.Evaluate(params, r.data(), jac);
  };
  for (int pass = 0; pass < 2; ++pass) {
    for (double s : {0.1, 0.5, 0.9}) {
      const gp::InterpolationWeights weights = gp::interpolationWeights(s * p.dt, p.dt);
      const GpProjectionFactor plain(Eigen::Vector2d(0.05, -0.02), weights, 0.005);
      GpProjectionFactor cached(Eigen::Vector2d(0.05, -0.02), weights, 0.005);
      cached.setSegmentCache(cache);
      Eigen::Vector2d r_plain, r_cached;
      std::array<std::vector<double>, 5> J_plain, J_cached;
      ASSERT_TRUE(evaluate(plain, r_plain, J_plain));
      ASSERT_TRUE(evaluate(cached, r_cached, J_cached));
      EXPECT_EQ(r_plain, r_cached) << "pass " << pass << " s " << s;
      for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(J_plain[i], J_cached[i]) << "block " << i;
    }
    // The second pass is at another evaluation point: the knots moved.
    values[2][0] += 0.01;
    values[3][4] -= 0.02;
  }
  // Three measurements per pass share one computation.
  EXPECT_EQ(cache->computed(), 2u);
  EXPECT_EQ(cache->reused(), 4u);
}

TEST(GpProjectionFactor, FailsBehindTheCamera) {
  const gp::InterpolationWeights weights = gp::interpolationWeights(0.01, 0.05);
  const GpProjectionFactor factor(Eigen::Vector2d(0.1, 0.1), weights, 0.01);
  const std::vector<double> pose = poseBlock(SE3()), vel(6, 0.0), behind = {0.0, 0.0, -1.0},
                            front = {0.0, 0.0, 1.0};
  const double* params_behind[] = {pose.data(), vel.data(), pose.data(), vel.data(), behind.data()};
  const double* params_front[] = {pose.data(), vel.data(), pose.data(), vel.data(), front.data()};
  Eigen::Vector2d r;
  EXPECT_FALSE(factor.Evaluate(params_behind, r.data(), nullptr));
  EXPECT_TRUE(factor.Evaluate(params_front, r.data(), nullptr));
  EXPECT_NEAR(r.x(), -10.0, 1e-12);
}

TEST(FixedPoseProjectionFactor, ResidualIsZeroAtTheTruthAndTheJacobianMatches) {
  std::mt19937 rng(9);
  const SE3 T_w_c = lie::se3::exp(randomVec6(rng, 1.0));
  const Eigen::Vector3d p_c(0.4, -0.3, 2.5);
  const Eigen::Vector3d p_w = T_w_c * p_c;
  const double sigma = 1.0 / 200.0;
  const FixedPoseProjectionFactor factor(T_w_c, p_c.head<2>() / p_c.z(), sigma);
  const std::vector<double> truth = {p_w.x(), p_w.y(), p_w.z()};
  const double* params[] = {truth.data()};
  Eigen::Vector2d r;
  ASSERT_TRUE(factor.Evaluate(params, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-9);
  const std::vector<double> off = {p_w.x() + 0.2, p_w.y() - 0.1, p_w.z() + 0.3};
  const double* params_off[] = {off.data()};
  ASSERT_TRUE(factor.Evaluate(params_off, r.data(), nullptr));
  EXPECT_GT(r.norm(), 1.0);  // 0.1-0.3 map units off at 2.5 m depth: many pixels
  for (const auto* v : {&truth, &off}) {
    const auto result = checkJacobians(factor, {*v}, {nullptr});
    ASSERT_TRUE(result.evaluated);
    EXPECT_LT(result.max_abs_error[0], 1e-6 * std::max(1.0, result.max_abs_numeric[0])) << result.report();
  }
  // Behind the camera: refused.
  const Eigen::Vector3d behind = T_w_c * Eigen::Vector3d(0.0, 0.0, -1.0);
  const std::vector<double> b = {behind.x(), behind.y(), behind.z()};
  const double* params_behind[] = {b.data()};
  EXPECT_FALSE(factor.Evaluate(params_behind, r.data(), nullptr));
}

TEST(StatePriorFactor, ResidualAndJacobians) {
  std::mt19937 rng(5);
  const SE3Manifold se3;
  const SE3 T_prior = lie::se3::exp(randomVec6(rng, 1.0));
  const Vec6 w_prior = randomVec6(rng, 0.5);
  gp::Mat12 A = gp::Mat12::Random();
  const gp::Mat12 P = A * A.transpose() * 1e-3 + 1e-4 * gp::Mat12::Identity();
  const StatePriorFactor factor(T_prior, w_prior, P);
  // At the prior mean the residual is zero.
  {
    const std::vector<double> a = poseBlock(T_prior), b = vecBlock(w_prior);
    const double* params[] = {a.data(), b.data()};
    gp::Vec12 r;
    ASSERT_TRUE(factor.Evaluate(params, r.data(), nullptr));
    EXPECT_LT(r.norm(), 1e-10);
    EXPECT_LT((factor.sqrtInformation().transpose() * factor.sqrtInformation() * P - gp::Mat12::Identity())
                  .cwiseAbs()
                  .maxCoeff(),
              1e-9);
  }
  const std::vector<std::vector<double>> values = {poseBlock(T_prior * lie::se3::exp(randomVec6(rng, 0.4))),
                                                   vecBlock(w_prior + randomVec6(rng, 0.1))};
  const auto result = checkJacobians(factor, values, {&se3, nullptr});
  ASSERT_TRUE(result.evaluated);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_LT(result.max_abs_error[i], 1e-8 * result.max_abs_numeric[i]) << result.report();
  }
}

TEST(LinearPriorFactor, SquareRootOfARankDeficientInformation) {
  std::mt19937 rng(6);
  std::normal_distribution<double> n(0.0, 1.0);
  // H = AᵀA with rank 9 out of 12 and b in its range.
  Eigen::MatrixXd A(9, 12);
  for (int i = 0; i < A.size(); ++i) A(i) = n(rng);
  const Eigen::MatrixXd H = A.transpose() * A;
  Eigen::VectorXd y(9);
  for (int i = 0; i < 9; ++i) y[i] = n(rng);
  const Eigen::VectorXd b = A.transpose() * y;
  const LinearPriorSqrt prior = linearPriorFromInformation(H, b);
  EXPECT_EQ(prior.rank, 9);
  EXPECT_LT((prior.J.transpose() * prior.J - H).cwiseAbs().maxCoeff(), 1e-11 * H.cwiseAbs().maxCoeff());
  EXPECT_LT((prior.J.transpose() * prior.r - b).cwiseAbs().maxCoeff(), 1e-11 * b.cwiseAbs().maxCoeff());
}

TEST(LinearPriorFactor, SquareRootOfAFullRankInformationKeepsItExactly) {
  std::mt19937 rng(16);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::MatrixXd A(14, 12);
  for (int i = 0; i < A.size(); ++i) A(i) = n(rng);
  const Eigen::MatrixXd H = A.transpose() * A;
  Eigen::VectorXd b(12);
  for (int i = 0; i < 12; ++i) b[i] = n(rng);
  const LinearPriorSqrt prior = linearPriorFromInformation(H, b);
  EXPECT_EQ(prior.rank, 12);
  EXPECT_LT((prior.J.transpose() * prior.J - H).cwiseAbs().maxCoeff(), 1e-12 * H.cwiseAbs().maxCoeff());
  EXPECT_LT((prior.J.transpose() * prior.r - b).cwiseAbs().maxCoeff(), 1e-12 * b.cwiseAbs().maxCoeff());
  // Full rank: the input itself is J*ᵀJ* and J*ᵀr*, and the factor uses it for its normal equations.
  EXPECT_EQ(prior.information, H);
  EXPECT_EQ(prior.gradient, b);
  std::vector<LinearPriorBlock> blocks(2);
  blocks[0].linearization_point = vecBlock(Vec6::Zero());
  blocks[1].linearization_point = vecBlock(Vec6::Ones());
  const LinearPriorFactor from_sqrt(blocks, prior);
  const LinearPriorFactor from_j(blocks, prior.J, prior.r);
  const std::vector<double> x0 = vecBlock(randomVec6(rng, 0.1));
  const std::vector<double> x1 = vecBlock(Vec6::Ones() + randomVec6(rng, 0.1));
  const double* params[] = {x0.data(), x1.data()};
  Eigen::MatrixXd H_sqrt, H_j;
  Eigen::VectorXd g_sqrt, g_j;
  from_sqrt.normalEquations(params, H_sqrt, g_sqrt);
  from_j.normalEquations(params, H_j, g_j);
  EXPECT_LT((H_sqrt - H_j).cwiseAbs().maxCoeff(), 1e-12 * H.cwiseAbs().maxCoeff());
  EXPECT_LT((g_sqrt - g_j).cwiseAbs().maxCoeff(), 1e-10 * (1 + g_j.cwiseAbs().maxCoeff()));
  LinearPriorSqrt wrong = prior;
  wrong.gradient.resize(11);
  EXPECT_THROW(LinearPriorFactor(blocks, wrong), std::invalid_argument);
}

TEST(LinearPriorFactor, SquareRootDropsTheNegativePartOfAnIndefiniteInformation) {
  // Rounding can leave a slightly negative direction in a Schur complement: it is dropped, not kept.
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, 3);
  H.diagonal() << 4.0, 1.0, -1e-9;
  const Eigen::VectorXd b = Eigen::Vector3d(2.0, 1.0, 0.0);
  const LinearPriorSqrt prior = linearPriorFromInformation(H, b);
  EXPECT_EQ(prior.rank, 2);
  Eigen::MatrixXd expected = H;
  expected(2, 2) = 0.0;
  EXPECT_LT((prior.J.transpose() * prior.J - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((prior.J.transpose() * prior.r - b).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(LinearPriorFactor, ResidualAndJacobiansOnPoseAndEuclideanBlocks) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  const SE3Manifold se3;
  const SE3 T_bar = lie::se3::exp(randomVec6(rng, 1.0));
  const Vec6 w_bar = randomVec6(rng, 0.5);
  std::vector<LinearPriorBlock> blocks(2);
  blocks[0].kind = LinearPriorBlock::Kind::kPose;
  blocks[0].linearization_point = poseBlock(T_bar);
  blocks[1].linearization_point = vecBlock(w_bar);
  Eigen::MatrixXd J(10, 12);
  for (int i = 0; i < J.size(); ++i) J(i) = n(rng);
  Eigen::VectorXd r(10);
  for (int i = 0; i < 10; ++i) r[i] = n(rng);
  const LinearPriorFactor factor(blocks, J, r);
  ASSERT_EQ(factor.num_residuals(), 10);
  ASSERT_EQ(factor.parameter_block_sizes(), (std::vector<int32_t>{7, 6}));

  // r(x) = r* + J*(x ⊟ x̄).
  const Vec6 d_pose = randomVec6(rng, 0.3);
  const Vec6 d_vel = randomVec6(rng, 0.2);
  const std::vector<std::vector<double>> values = {poseBlock(T_bar * lie::se3::exp(d_pose)),
                                                   vecBlock(w_bar + d_vel)};
  const double* params[] = {values[0].data(), values[1].data()};
  Eigen::VectorXd res(10);
  ASSERT_TRUE(factor.Evaluate(params, res.data(), nullptr));
  Eigen::VectorXd dx(12);
  dx << d_pose, d_vel;
  EXPECT_LT((res - (r + J * dx)).norm(), 1e-12);

  const auto result = checkJacobians(factor, values, {&se3, nullptr});
  ASSERT_TRUE(result.evaluated);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_LT(result.max_abs_error[i], 1e-8 * result.max_abs_numeric[i]) << result.report();
  }
}

TEST(LinearPriorFactor, NormalEquationsEqualThoseOfItsJacobian) {
  // H = JᵀJ and g = Jᵀr from the stored J*ᵀJ*, J*ᵀr* equal those formed from Evaluate's J and r, away
  // from the linearization point (where J_r⁻¹ ≠ I) and with two pose blocks around a Euclidean one.
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<LinearPriorBlock> blocks(3);
  std::vector<std::vector<double>> values;
  for (int b = 0; b < 3; ++b) {
    if (b != 1) {
      const SE3 T_bar = lie::se3::exp(randomVec6(rng, 1.0));
      blocks[b].kind = LinearPriorBlock::Kind::kPose;
      blocks[b].linearization_point = poseBlock(T_bar);
      values.push_back(poseBlock(T_bar * lie::se3::exp(randomVec6(rng, 0.4))));
    } else {
      const Vec6 w_bar = randomVec6(rng, 0.5);
      blocks[b].linearization_point = vecBlock(w_bar);
      values.push_back(vecBlock(w_bar + randomVec6(rng, 0.3)));
    }
  }
  Eigen::MatrixXd J(14, 18);
  for (int i = 0; i < J.size(); ++i) J(i) = n(rng);
  Eigen::VectorXd r(14);
  for (int i = 0; i < 14; ++i) r[i] = n(rng);
  const LinearPriorFactor factor(blocks, J, r);

  const double* params[] = {values[0].data(), values[1].data(), values[2].data()};
  Eigen::VectorXd res(14);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor J0(14, 7), J1(14, 6), J2(14, 7);
  double* jacobians[] = {J0.data(), J1.data(), J2.data()};
  ASSERT_TRUE(factor.Evaluate(params, res.data(), jacobians));
  Eigen::MatrixXd J_tangent(14, 18);
  J_tangent << J0.leftCols<6>(), J1, J2.leftCols<6>();
  const Eigen::MatrixXd H_expected = J_tangent.transpose() * J_tangent;
  const Eigen::VectorXd g_expected = J_tangent.transpose() * res;

  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  factor.normalEquations(params, H, g);
  ASSERT_EQ(H.rows(), 18);
  EXPECT_LT((H - H_expected).cwiseAbs().maxCoeff(), 1e-10 * H_expected.cwiseAbs().maxCoeff());
  EXPECT_LT((g - g_expected).cwiseAbs().maxCoeff(), 1e-10 * g_expected.cwiseAbs().maxCoeff());
  // The correction matters here: J*ᵀJ* alone is not the answer.
  EXPECT_GT((factor.jacobian().transpose() * factor.jacobian() - H_expected).cwiseAbs().maxCoeff(),
            1e-3 * H_expected.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace asynevo::backend
