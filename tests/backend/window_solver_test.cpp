// The builtin window solver (backend/window_solver.hpp) against Ceres on the same GP bundle-adjustment
// windows: the same minimum, landmarks coupled by a prior kept in the dense system, constant blocks
// left alone, steps into a point behind the camera rejected.

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <string>

#include "asynevo/backend/factors/gp_projection_factor.hpp"
#include "asynevo/backend/factors/linear_prior_factor.hpp"
#include "asynevo/backend/factors/segment_cache.hpp"
#include "asynevo/backend/factors/state_prior_factor.hpp"
#include "asynevo/backend/window_solver.hpp"
#include "testing/gp_ba_sim.hpp"

namespace asynevo::backend {
namespace {

using testing::GpBaConfig;
using testing::GpBaScenario;
using testing::GpBaState;

/// The scenario's factors over the blocks of `x`, as the estimator lists them (WNOA priors, then
/// projections with a Huber loss), with every block's kind.
struct Window {
  std::vector<FactorEntry> factors;
  std::map<double*, BlockKind> kinds;
  std::set<const double*> landmarks;
};

Window makeWindow(const GpBaScenario& s, GpBaState& x, double huber) {
  Window w;
  const lie::Mat6 Q_c = s.config.q_c * lie::Mat6::Identity();
  for (std::size_t k = 0; k < x.poses.size(); ++k) {
    w.kinds[x.poses[k].data()] = BlockKind::kPose;
    w.kinds[x.velocities[k].data()] = BlockKind::kEuclidean;
  }
  for (std::size_t k = 0; k + 1 < x.poses.size(); ++k) {
    w.factors.push_back({std::make_shared<WnoaPriorFactor>(s.knot_times_ns[k], s.knot_times_ns[k + 1], Q_c), nullptr,
                         {x.poses[k].data(), x.velocities[k].data(), x.poses[k + 1].data(), x.velocities[k + 1].data()}});
  }
  auto loss = std::make_shared<ceres::HuberLoss>(huber);
  for (const testing::GpBaMeasurement& m : s.measurements) {
    const int k = m.knot;
    double* p = x.landmarks[m.landmark].data();
    w.kinds[p] = BlockKind::kEuclidean;
    w.landmarks.insert(p);
    w.factors.push_back({std::make_shared<GpProjectionFactor>(m.z, m.t_ns, s.knot_times_ns[k], s.knot_times_ns[k + 1],
                                                              s.config.sigma),
                         loss,
                         {x.poses[k].data(), x.velocities[k].data(), x.poses[k + 1].data(), x.velocities[k + 1].data(), p}});
  }
  return w;
}

double solveWithCeres(const Window& w, const std::set<const double*>& constant, int max_iterations) {
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  SE3Manifold manifold;
  for (const FactorEntry& f : w.factors) problem.AddResidualBlock(f.cost.get(), f.loss.get(), f.blocks);
  for (const auto& [block, kind] : w.kinds)
    if (kind == BlockKind::kPose && problem.HasParameterBlock(block)) problem.SetManifold(block, &manifold);
  for (const double* b : constant) problem.SetParameterBlockConstant(const_cast<double*>(b));
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary.final_cost;
}

double maxPoseDifference(const GpBaState& a, const GpBaState& b) {
  double d = 0.0;
  for (std::size_t k = 0; k < a.poses.size(); ++k)
    d = std::max(d, lie::se3::boxMinus(poseFromBlock(a.poses[k].data()), poseFromBlock(b.poses[k].data()))
                        .cwiseAbs()
                        .maxCoeff());
  return d;
}

/// Every knot and landmark of `x` equal to `expected`'s bit for bit; `label` names the case in failures.
void expectSameState(const GpBaState& x, const GpBaState& expected, const std::string& label) {
  for (std::size_t k = 0; k < x.poses.size(); ++k) {
    EXPECT_EQ(x.poses[k], expected.poses[k]) << label << ", knot " << k;
    EXPECT_EQ(x.velocities[k], expected.velocities[k]) << label << ", knot " << k;
  }
  for (std::size_t l = 0; l < x.landmarks.size(); ++l)
    EXPECT_EQ(x.landmarks[l], expected.landmarks[l]) << label << ", landmark " << l;
}

class WindowSolverTest : public ::testing::Test {
 protected:
  void SetUp() override {
    GpBaConfig config;
    config.knots = 12;
    config.landmarks = 60;
    config.measurements_per_landmark = 12;
    scenario_ = testing::makeGpBaScenario(config);
    start_ = withTrueEnds(testing::perturbedState(scenario_, 5));
  }
  /// x with its first and last pose set to the truth's (gauge and scale: held constant by constantOf).
  GpBaState withTrueEnds(GpBaState x) const {
    const GpBaState truth = testing::stateFromTruth(scenario_);
    x.poses.front() = truth.poses.front();
    x.poses.back() = truth.poses.back();
    return x;
  }
  std::set<const double*> constantOf(const GpBaState& x) const {
    return {x.poses.front().data(), x.poses.back().data()};
  }

  /// Both solvers from the start, `iterations` each, on windows built alike.
  struct BothSolved {
    GpBaState x_ceres, x_own;
    double ceres_cost = 0.0;
    WindowSolverSummary own;
  };
  BothSolved solveBoth(int iterations) {
    BothSolved b{start_, start_, 0.0, {}};
    const Window w_ceres = makeWindow(scenario_, b.x_ceres, 2.0);
    const Window w_own = makeWindow(scenario_, b.x_own, 2.0);
    b.ceres_cost = solveWithCeres(w_ceres, constantOf(b.x_ceres), iterations);
    WindowSolverOptions options;
    options.max_iterations = iterations;
    b.own = solveWindow(w_own.factors, w_own.kinds, w_own.landmarks, constantOf(b.x_own), manifold_, options);
    return b;
  }

  GpBaScenario scenario_;
  GpBaState start_;
  SE3Manifold manifold_;
};

TEST_F(WindowSolverTest, ReachesTheMinimumCeresReaches) {
  const BothSolved b = solveBoth(50);
  const WindowSolverSummary& summary = b.own;
  ASSERT_TRUE(summary.valid_start);
  EXPECT_EQ(summary.eliminated_landmarks, 60);
  EXPECT_EQ(summary.reduced_dims, 12 * 12 - 2 * 6);  // knots' poses and twists, two poses constant
  EXPECT_GT(summary.initial_cost, 1e3 * summary.final_cost);
  EXPECT_NEAR(summary.final_cost, b.ceres_cost, 1e-6 * b.ceres_cost + 1e-9);
  EXPECT_LT(maxPoseDifference(b.x_own, b.x_ceres), 1e-6);
  // Close to the truth (the floor is the truth not being exactly WNOA).
  EXPECT_LT(testing::positionRmse(scenario_, b.x_own), 5e-3);
}

TEST_F(WindowSolverTest, FewIterationsDescendLikeCeres) {
  // The estimator runs 5 iterations per window: both solvers take the same kind of steps.
  const BothSolved b = solveBoth(3);
  EXPECT_LE(b.own.iterations, 4);
  EXPECT_LT(b.own.final_cost, 0.1 * b.own.initial_cost);
  EXPECT_NEAR(b.own.final_cost, b.ceres_cost, 0.05 * b.ceres_cost);
}

TEST_F(WindowSolverTest, ChordStepsReachTheSameMinimumWithFewerLinearizations) {
  // relinearize_every k: Jacobians at every k-th step taken, the steps between reuse them with the
  // gradient at the new values. The gradient is exact, so the minimum is the same.
  const BothSolved reference = solveBoth(60);
  for (int k : {2, 3}) {
    GpBaState x = start_;
    const Window w = makeWindow(scenario_, x, 2.0);
    WindowSolverOptions options;
    options.max_iterations = 60;
    options.relinearize_every = k;
    const WindowSolverSummary summary = solveWindow(w.factors, w.kinds, w.landmarks, constantOf(x), manifold_, options);
    ASSERT_TRUE(summary.valid_start) << k;
    EXPECT_NEAR(summary.final_cost, reference.ceres_cost, 1e-6 * reference.ceres_cost + 1e-9) << k;
    EXPECT_LT(maxPoseDifference(x, reference.x_own), 1e-6) << k;
    // One linearization at the start, then at most one per k steps taken (and one after a rejection).
    const int rejected = summary.iterations - 1 - summary.accepted_steps;
    EXPECT_LE(summary.linearizations, 1 + summary.accepted_steps / k + rejected) << k;
    EXPECT_LT(summary.linearizations, summary.accepted_steps) << k;
  }
  // k = 1, the default, linearizes at every step taken but the last.
  EXPECT_EQ(WindowSolverOptions{}.relinearize_every, 1);
  EXPECT_GE(reference.own.linearizations, reference.own.accepted_steps);
}

TEST_F(WindowSolverTest, AWarmStartGetsCloserToTheMinimumWithLessInitialDamping) {
  // A window solve starts next to its minimum (the previous window's solution). Ceres's initial
  // trust-region radius (1e4) damps the first steps of such a start; a wider one (the estimator's
  // backend.initial_trust_region_radius) takes nearly Gauss-Newton steps and gets closer in as many.
  const BothSolved reference = solveBoth(60);
  const double minimum = reference.own.final_cost;
  const GpBaState near = withTrueEnds(testing::perturbedState(scenario_, 7, 0.002, 0.002, 0.005, 0.005));
  auto gapAfter = [&](double radius, int iterations) {
    GpBaState x = near;
    const Window w = makeWindow(scenario_, x, 2.0);
    WindowSolverOptions options;
    options.max_iterations = iterations;
    options.function_tolerance = 0.0;
    options.initial_radius = radius;
    const WindowSolverSummary summary = solveWindow(w.factors, w.kinds, w.landmarks, constantOf(x), manifold_, options);
    EXPECT_TRUE(summary.valid_start);
    EXPECT_GE(summary.final_cost, minimum * (1.0 - 1e-9));
    return summary.final_cost - minimum;
  };
  const double start_gap = gapAfter(1e4, 0);
  const double ceres_default = gapAfter(1e4, 2);
  const double wide = gapAfter(1e6, 2);
  EXPECT_LT(ceres_default, start_gap);
  // Measured: the cost 305 above the minimum at the start, 8.3e-4 after two steps from 1e4, 1.1e-7 from 1e6.
  EXPECT_LT(wide, 0.01 * ceres_default) << "after two steps: " << wide << " (1e6) against " << ceres_default << " (1e4)";
}

TEST_F(WindowSolverTest, ConstantBlocksDoNotMove) {
  GpBaState x = start_;
  const Window w = makeWindow(scenario_, x, 2.0);
  std::set<const double*> constant = constantOf(x);
  constant.insert(x.velocities[3].data());
  constant.insert(x.landmarks[7].data());
  const auto velocity = x.velocities[3];
  const auto landmark = x.landmarks[7];
  const auto first = x.poses.front();
  WindowSolverOptions options;
  options.max_iterations = 10;
  const WindowSolverSummary summary = solveWindow(w.factors, w.kinds, w.landmarks, constant, manifold_, options);
  EXPECT_EQ(summary.eliminated_landmarks, 59);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  EXPECT_EQ(x.velocities[3], velocity);
  EXPECT_EQ(x.landmarks[7], landmark);
  EXPECT_EQ(x.poses.front(), first);
  EXPECT_NE(x.landmarks[8], start_.landmarks[8]);
}

TEST_F(WindowSolverTest, LandmarksCoupledByAPriorStayInTheDenseSystem) {
  // A linear prior on two landmarks (as the marginalization prior's blanket can hold): neither can be
  // eliminated alone; the solution still matches Ceres.
  GpBaState x_ceres = start_;
  GpBaState x_own = start_;
  Window w_ceres = makeWindow(scenario_, x_ceres, 2.0);
  Window w_own = makeWindow(scenario_, x_own, 2.0);
  auto addPrior = [&](Window& w, GpBaState& x) {
    std::vector<LinearPriorBlock> blocks(2);
    blocks[0].linearization_point.assign(x.landmarks[0].begin(), x.landmarks[0].end());
    blocks[1].linearization_point.assign(x.landmarks[1].begin(), x.landmarks[1].end());
    Eigen::MatrixXd J = 10.0 * Eigen::MatrixXd::Identity(6, 6);
    J.block<3, 3>(0, 3) = -5.0 * Eigen::Matrix3d::Identity();
    w.factors.push_back({std::make_shared<LinearPriorFactor>(std::move(blocks), J, Eigen::VectorXd::Constant(6, 0.1)),
                         nullptr,
                         {x.landmarks[0].data(), x.landmarks[1].data()}});
  };
  addPrior(w_ceres, x_ceres);
  addPrior(w_own, x_own);
  const double ceres_cost = solveWithCeres(w_ceres, constantOf(x_ceres), 50);
  WindowSolverOptions options;
  options.max_iterations = 50;
  const WindowSolverSummary summary =
      solveWindow(w_own.factors, w_own.kinds, w_own.landmarks, constantOf(x_own), manifold_, options);
  EXPECT_EQ(summary.eliminated_landmarks, 58);
  EXPECT_EQ(summary.reduced_dims, 12 * 12 - 2 * 6 + 2 * 3);
  EXPECT_NEAR(summary.final_cost, ceres_cost, 1e-6 * ceres_cost + 1e-9);
  EXPECT_LT(maxPoseDifference(x_own, x_ceres), 1e-6);
  for (int l = 0; l < 2; ++l)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(x_own.landmarks[l][c], x_ceres.landmarks[l][c], 1e-6);
}

TEST_F(WindowSolverTest, AStartBehindTheCameraIsReportedAndNothingMoves) {
  GpBaState x = start_;
  const Window w = makeWindow(scenario_, x, 2.0);
  // Landmark 0 moved behind every camera that sees it: its projections refuse to evaluate.
  const auto& m = *std::find_if(scenario_.measurements.begin(), scenario_.measurements.end(),
                                [](const testing::GpBaMeasurement& mm) { return mm.landmark == 0; });
  const lie::SE3 T = poseFromBlock(x.poses[m.knot].data());
  const Eigen::Vector3d behind = T * Eigen::Vector3d(0.0, 0.0, -3.0);
  std::copy(behind.data(), behind.data() + 3, x.landmarks[0].data());
  const GpBaState before = x;
  const WindowSolverSummary summary = solveWindow(w.factors, w.kinds, w.landmarks, constantOf(x), manifold_, {});
  EXPECT_FALSE(summary.valid_start);
  EXPECT_EQ(x.poses, before.poses);
  EXPECT_EQ(x.velocities, before.velocities);
  EXPECT_EQ(x.landmarks[5], before.landmarks[5]);
}

/// r = p₀ − 10 on a 3-vector, refusing to evaluate beyond p₀ = 5 (as a projection refuses a point
/// behind the camera).
class WallCost final : public ceres::SizedCostFunction<1, 3> {
 public:
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    if (p[0][0] > 5.0) return false;
    r[0] = p[0][0] - 10.0;
    if (J && J[0]) {
      J[0][0] = 1.0;
      J[0][1] = J[0][2] = 0.0;
    }
    return true;
  }
};

TEST_F(WindowSolverTest, FactorsEvaluatedOnSeveralThreadsGiveTheSameResultBitForBit) {
  // 731 factors: 1 thread, 3 threads (ranges of unequal factor kinds), and 8. The projections of a knot
  // interval share its segment cache, which the threads then use concurrently.
  auto solve = [&](int threads, GpBaState& x) {
    Window w = makeWindow(scenario_, x, 2.0);
    std::map<const double*, std::shared_ptr<SegmentCache>> caches;
    for (const FactorEntry& f : w.factors) {
      auto* projection = dynamic_cast<GpProjectionFactor*>(f.cost.get());
      if (projection == nullptr) continue;
      std::shared_ptr<SegmentCache>& cache = caches[f.blocks[0]];
      if (!cache) cache = std::make_shared<SegmentCache>();
      projection->setSegmentCache(cache);
    }
    WindowSolverOptions options;
    options.max_iterations = 8;
    options.threads = threads;
    return solveWindow(w.factors, w.kinds, w.landmarks, constantOf(x), manifold_, options);
  };
  GpBaState one = start_;
  const WindowSolverSummary a = solve(1, one);
  ASSERT_TRUE(a.valid_start);
  ASSERT_LT(a.final_cost, 1e-3 * a.initial_cost);
  EXPECT_EQ(a.evaluation_threads, 1);
  for (const int threads : {3, 8}) {
    GpBaState x = start_;
    const WindowSolverSummary b = solve(threads, x);
    EXPECT_EQ(b.evaluation_threads, threads);
    EXPECT_EQ(b.initial_cost, a.initial_cost) << threads;
    EXPECT_EQ(b.final_cost, a.final_cost) << threads;
    EXPECT_EQ(b.iterations, a.iterations) << threads;
    expectSameState(x, one, std::to_string(threads) + " threads");
  }
}

TEST_F(WindowSolverTest, AReusedWorkspaceGivesTheSameResultBitForBit) {
  // One workspace through the whole window, then a smaller one (its buffers then hold the larger
  // solve's values beyond the smaller one's sizes), then the whole window again: each solve as a solve
  // with buffers of its own.
  auto solve = [&](GpBaState& x, bool drop_projections, WindowSolverWorkspace* workspace) {
    Window w = makeWindow(scenario_, x, 2.0);
    if (drop_projections) w.factors.resize(w.factors.size() / 2);
    WindowSolverOptions options;
    options.max_iterations = 6;
    return solveWindow(w.factors, w.kinds, w.landmarks, constantOf(x), manifold_, options, workspace);
  };
  WindowSolverWorkspace workspace;
  for (const bool smaller : {false, true, false}) {
    GpBaState fresh = start_, reused = start_;
    const WindowSolverSummary a = solve(fresh, smaller, nullptr);
    const WindowSolverSummary b = solve(reused, smaller, &workspace);
    ASSERT_TRUE(a.valid_start);
    ASSERT_LT(a.final_cost, a.initial_cost) << "smaller " << smaller;
    EXPECT_EQ(b.final_cost, a.final_cost) << "smaller " << smaller;
    EXPECT_EQ(b.iterations, a.iterations) << "smaller " << smaller;
    EXPECT_EQ(b.reduced_dims, a.reduced_dims) << "smaller " << smaller;
    expectSameState(reused, fresh, smaller ? "smaller window" : "whole window");
  }
}

TEST_F(WindowSolverTest, AFewFactorsAreEvaluatedOnOneThread) {
  // 11 WNOA priors alone: fewer than one thread's share, whatever is asked.
  GpBaState x = start_;
  Window w = makeWindow(scenario_, x, 2.0);
  w.factors.resize(x.poses.size() - 1);
  w.landmarks.clear();
  WindowSolverOptions options;
  options.threads = 4;
  const WindowSolverSummary summary =
      solveWindow(w.factors, w.kinds, w.landmarks, constantOf(x), manifold_, options);
  EXPECT_EQ(summary.evaluation_threads, 1);
}

TEST(WindowSolver, StepsWhereAFactorRefusesToEvaluateAreRejected) {
  // The Gauss–Newton step goes to p₀ = 10, where the factor refuses: the step is rejected, the trust
  // region shrinks and the accepted steps approach the wall from below.
  std::array<double, 3> p{0.0, 1.0, 2.0};
  const std::vector<FactorEntry> factors{{std::make_shared<WallCost>(), nullptr, {p.data()}}};
  const std::map<double*, BlockKind> kinds{{p.data(), BlockKind::kEuclidean}};
  SE3Manifold manifold;
  WindowSolverOptions options;
  options.max_iterations = 30;
  options.initial_radius = 1e8;
  const WindowSolverSummary summary = solveWindow(factors, kinds, {p.data()}, {}, manifold, options);
  ASSERT_TRUE(summary.valid_start);
  EXPECT_EQ(summary.eliminated_landmarks, 1);
  EXPECT_DOUBLE_EQ(summary.initial_cost, 50.0);
  EXPECT_GT(summary.accepted_steps, 0);
  EXPECT_GT(summary.iterations, summary.accepted_steps + 1);  // some steps were rejected
  EXPECT_GT(p[0], 2.0);
  EXPECT_LE(p[0], 5.0);
  EXPECT_LT(summary.final_cost, 32.0);  // (p₀ − 10)²/2 with p₀ > 2
  EXPECT_EQ(p[1], 1.0);                 // no gradient along the other coordinates
  EXPECT_EQ(p[2], 2.0);
}

}  // namespace
}  // namespace asynevo::backend
