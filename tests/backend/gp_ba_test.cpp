// Whole-problem tests of the GP factors (issue 5 item 4; reference/backend.md §5.6–5.7).

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>

#include "testing/gp_ba_sim.hpp"

namespace asynevo::backend {
namespace {

using testing::GpBaConfig;
using testing::GpBaScenario;
using testing::GpBaState;

// Solves the scenario from `x`, with the gauge and scale fixed by holding the first and the last knot
// pose at the truth. (Monocular scale is only weakly observable through the prior, which pulls toward a
// smaller scale, reference/backend.md §2: anchoring it with the first velocity alone leaves a 3.6 %
// scale shrink on this scenario.)
ceres::Solver::Summary solve(const GpBaScenario& s, GpBaState& x) {
  const GpBaState truth = testing::stateFromTruth(s);
  x.poses.front() = truth.poses.front();
  x.poses.back() = truth.poses.back();
  ceres::Problem problem;
  testing::buildGpBaProblem(s, x, problem);
  problem.SetParameterBlockConstant(x.poses.front().data());
  problem.SetParameterBlockConstant(x.poses.back().data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = 50;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary;
}

TEST(GpBundleAdjustment, NoiseFreeProblemConvergesToTheTruth) {
  // 20 knots at 50 ms, 300 landmarks, 3000 noise-free measurements (reference/backend.md §5.7).
  const GpBaScenario s = testing::makeGpBaScenario(GpBaConfig{});
  ASSERT_EQ(s.measurements.size(), 3000u);
  GpBaState x = testing::perturbedState(s, 11);  // 2 cm / 1.1° per knot, 5 cm per landmark
  const double rmse_start = testing::positionRmse(s, x);
  const ceres::Solver::Summary summary = solve(s, x);
  const double rmse = testing::positionRmse(s, x);
  std::printf(
      "GP-BA from a perturbed start: %d iterations, cost %.3e -> %.3e, position RMSE %.2f mm -> %.3f mm\n",
      static_cast<int>(summary.iterations.size()), summary.initial_cost, summary.final_cost, 1e3 * rmse_start,
      1e3 * rmse);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  EXPECT_EQ(summary.termination_type, ceres::CONVERGENCE);
  EXPECT_GT(rmse_start, 0.02);
  // Millimetre level: the floor is the truth not being exactly WNOA (measured 2.5 mm with Q_c = I at
  // 50 ms knots; the reference note reports 2.9 mm for its scenario).
  EXPECT_LT(rmse, 4e-3);

  // The perturbed start reaches the same optimum as a start at the truth.
  GpBaState from_truth = testing::stateFromTruth(s);
  solve(s, from_truth);
  double max_diff = 0.0;
  for (size_t k = 0; k < x.poses.size(); ++k) {
    const lie::Vec6 d = lie::se3::boxMinus(backend::poseFromBlock(x.poses[k].data()),
                                           backend::poseFromBlock(from_truth.poses[k].data()));
    max_diff = std::max(max_diff, d.cwiseAbs().maxCoeff());
  }
  EXPECT_LT(max_diff, 1e-6);
}

TEST(GpBundleAdjustment, JacobianNullSpaceAtTheTruthIsTheSixDofGauge) {
  GpBaConfig config;
  config.landmarks = 150;  // keeps the dense eigen-decomposition small
  const GpBaScenario s = testing::makeGpBaScenario(config);
  GpBaState x = testing::stateFromTruth(s);
  ceres::Problem problem;
  testing::buildGpBaProblem(s, x, problem);

  ceres::CRSMatrix crs;
  ASSERT_TRUE(problem.Evaluate(ceres::Problem::EvaluateOptions(), nullptr, nullptr, nullptr, &crs));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int i = crs.rows[row]; i < crs.rows[row + 1]; ++i) J(row, crs.cols[i]) = crs.values[i];
  }
  // Tangent columns: 20 poses × 6 + 20 velocities × 6 + landmarks × 3.
  ASSERT_EQ(J.cols(), config.knots * 12 + config.landmarks * 3);
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  const double lambda_max = lambda[lambda.size() - 1];
  std::printf("J^T J eigenvalues: smallest 8 =");
  for (int i = 0; i < 8; ++i) std::printf(" %.2e", lambda[i]);
  std::printf(", largest %.2e\n", lambda_max);
  // Six numerically-zero eigenvalues (global SE(3) gauge), then a clear gap: the 7th (monocular scale,
  // weakly observed through the prior) and the rest are far above round-off.
  for (int i = 0; i < 6; ++i) EXPECT_LT(std::abs(lambda[i]), 1e-12 * lambda_max) << i;
  EXPECT_GT(lambda[6], 1e-11 * lambda_max);
  EXPECT_GT(lambda[6], 1e3 * std::abs(lambda[5]));

  // The null space is the gauge: a global left multiplication T_k ← Exp(g)T_k, p ← Exp(g)p, with
  // ϖ unchanged, gives zero first-order change. Build its tangent direction and check J·v ≈ 0.
  Eigen::MatrixXd gauge = Eigen::MatrixXd::Zero(J.cols(), 6);
  for (int k = 0; k < config.knots; ++k) {
    // Left perturbation Exp(g)T = T Exp(Ad(T⁻¹)g).
    gauge.block<6, 6>(6 * k, 0) = lie::se3::adjointInverse(s.poses[k]);
  }
  for (int j = 0; j < config.landmarks; ++j) {
    // Exp(g)p ≈ p + ρ + φ × p = p + [I, −p^] g.
    gauge.block<3, 3>(config.knots * 12 + 3 * j, 0).setIdentity();
    gauge.block<3, 3>(config.knots * 12 + 3 * j, 3) = -lie::so3::hat(s.landmarks[j]);
  }
  // Ceres orders the columns by parameter-block insertion: poses and velocities interleaved.
  Eigen::MatrixXd gauge_ceres = Eigen::MatrixXd::Zero(J.cols(), 6);
  for (int k = 0; k < config.knots; ++k) gauge_ceres.block<6, 6>(12 * k, 0) = gauge.block<6, 6>(6 * k, 0);
  gauge_ceres.bottomRows(config.landmarks * 3) = gauge.bottomRows(config.landmarks * 3);
  const double j_norm = J.cwiseAbs().maxCoeff();
  EXPECT_LT((J * gauge_ceres).cwiseAbs().maxCoeff(), 1e-9 * j_norm);
}

}  // namespace
}  // namespace asynevo::backend
