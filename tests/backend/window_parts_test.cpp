// Unit tests of the sliding window's parts: scale anchor factor, triangulation, Triggs-corrected
// linearization and the Schur-complement marginalization.
#include <ceres/loss_function.h>
#include <ceres/sized_cost_function.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "asynevo/backend/factor_graph.hpp"
#include "asynevo/backend/factors/pose_block.hpp"
#include "asynevo/backend/factors/scale_anchor_factor.hpp"
#include "asynevo/backend/factors/se3_manifold.hpp"
#include "asynevo/backend/marginalization.hpp"
#include "asynevo/backend/trajectory.hpp"
#include "asynevo/backend/triangulation.hpp"
#include "testing/jacobian_check.hpp"

namespace asynevo::backend {
namespace {

std::vector<double> poseBlock(const lie::SE3& T) {
  std::vector<double> x(7);
  poseToBlock(T, x.data());
  return x;
}

TEST(ScaleAnchorFactor, JacobiansMatchNumericThroughTheManifold) {
  const SE3Manifold se3;
  const lie::SE3 T_a(lie::so3::exp(Eigen::Vector3d(0.3, -0.2, 0.1)), Eigen::Vector3d(0.1, 0.2, -0.3));
  const lie::SE3 T_b(lie::so3::exp(Eigen::Vector3d(-0.1, 0.4, 0.2)), Eigen::Vector3d(1.1, -0.4, 0.5));
  const ScaleAnchorFactor factor(1.0, 0.01);
  const auto result = testing::checkJacobians(factor, {poseBlock(T_a), poseBlock(T_b)}, {&se3, &se3});
  ASSERT_TRUE(result.evaluated);
  EXPECT_LT(result.worstError(), 1e-6) << result.report();
  double r = 0;
  const std::vector<double> a = poseBlock(T_a), b = poseBlock(T_b);
  const double* blocks[2] = {a.data(), b.data()};
  ASSERT_TRUE(factor.Evaluate(blocks, &r, nullptr));
  EXPECT_NEAR(r, ((T_b.translation() - T_a.translation()).norm() - 1.0) / 0.01, 1e-9);
}

/// n exact views of p_w from cameras stepping `baseline` along x and turning `turn` rad about y each.
std::vector<TriangulationView> exactViews(const Eigen::Vector3d& p_w, int n, double turn, double baseline) {
  std::vector<TriangulationView> views;
  for (int i = 0; i < n; ++i) {
    const lie::SE3 T_w_c(lie::so3::exp(Eigen::Vector3d(0, turn * i, 0)), Eigen::Vector3d(baseline * i, 0, 0));
    const Eigen::Vector3d p_c = T_w_c.inverse() * p_w;
    views.push_back({T_w_c, p_c.head<2>() / p_c.z()});
  }
  return views;
}

TEST(Triangulation, RecoversAPointAndRejectsBadGeometry) {
  const Eigen::Vector3d p_w(0.3, -0.2, 4.0);
  std::vector<TriangulationView> views = exactViews(p_w, 5, 0.02, 0.1);
  TriangulationOptions options;
  const TriangulationResult ok = triangulate(views, options);
  ASSERT_TRUE(ok.p_w) << triangulationFailureName(ok.failure);
  EXPECT_LT((*ok.p_w - p_w).norm(), 1e-9);
  // World-frame rays from the first and the last camera centre (the largest angle here).
  const Eigen::Vector3d ray0 = p_w.normalized(), ray4 = (p_w - Eigen::Vector3d(0.4, 0, 0)).normalized();
  EXPECT_NEAR(ok.parallax_deg, std::acos(ray0.dot(ray4)) * 180 / M_PI, 1e-6);

  EXPECT_EQ(triangulate({views[0]}, options).failure, TriangulationFailure::kTooFewViews);
  std::vector<TriangulationView> same(3, views[0]);
  EXPECT_EQ(triangulate(same, options).failure, TriangulationFailure::kLowParallax);
  options.min_depth = 5.0;  // the point is at depth ~4
  EXPECT_EQ(triangulate(views, options).failure, TriangulationFailure::kBehindCamera);
  options.min_depth = 0.05;
  views[2].xn += Eigen::Vector2d(0.05, 0);  // a 10 px outlier
  EXPECT_EQ(triangulate(views, options).failure, TriangulationFailure::kHighError);
}

TEST(Triangulation, TheRmsTestAdmitsOnePoorViewAmongManyButNotAPoorTrajectory) {
  // 20 exact views of a point at depth 4 from cameras 5 cm apart (focal length 200 px, so the 3 px
  // bound is 0.015), then one view moved by 6 px: its error after the refinement is still above the
  // bound, the RMS over the 20 views is well below it.
  const Eigen::Vector3d p_w(0.3, -0.2, 4.0);
  std::vector<TriangulationView> views = exactViews(p_w, 20, 0.01, 0.05);
  views[10].xn += Eigen::Vector2d(0.03, 0);
  TriangulationOptions largest;
  largest.max_error = 0.015;
  TriangulationOptions rms = largest;
  rms.rms_error = true;
  const TriangulationResult by_largest = triangulate(views, largest);
  EXPECT_EQ(by_largest.failure, TriangulationFailure::kHighError);
  EXPECT_GT(by_largest.max_error, 0.015);
  const TriangulationResult by_rms = triangulate(views, rms);
  ASSERT_TRUE(by_rms.p_w) << triangulationFailureName(by_rms.failure);
  EXPECT_LT(by_rms.rms_error, 0.015);
  EXPECT_NEAR(by_rms.max_error, by_largest.max_error, 1e-12);  // the same point, only the test differs
  EXPECT_LT((*by_rms.p_w - p_w).norm(), 0.2);
  // Every view 4 px off in alternating directions: no RMS below 3 px, rejected either way.
  for (int i = 0; i < 20; ++i) views[i].xn.y() += (i % 2 ? 0.02 : -0.02);
  EXPECT_EQ(triangulate(views, rms).failure, TriangulationFailure::kHighError);
}

TEST(Triangulation, ATrajectoryIsTriangulatedFromTheViewsItsRuleAllows) {
  // 8 exact views of a point at depth 4; the last 3 lie on knots added since the latest solve, and
  // their camera poses are 20 cm off across the rays (as a constant-velocity prediction under
  // acceleration can be): about 10 px.
  const Eigen::Vector3d p_w(0.3, -0.2, 4.0);
  std::vector<TriangulationView> views = exactViews(p_w, 8, 0.01, 0.05);
  const std::size_t solved = 5;
  for (std::size_t i = solved; i < views.size(); ++i)
    views[i].T_w_c = lie::SE3(views[i].T_w_c.rotation(), views[i].T_w_c.translation() + Eigen::Vector3d(0, 0.2, 0));
  TriangulationOptions options;
  options.max_error = 0.015;  // 3 px at a focal length of 200 px
  const TriangulationResult all = triangulateTrajectory(views, solved, TriangulationViews::kAll, 5, options);
  EXPECT_EQ(all.failure, TriangulationFailure::kHighError);
  for (const TriangulationViews rule : {TriangulationViews::kSolved, TriangulationViews::kSolvedThenAll}) {
    const TriangulationResult r = triangulateTrajectory(views, solved, rule, 5, options);
    ASSERT_TRUE(r.p_w) << triangulationFailureName(r.failure);
    EXPECT_LT((*r.p_w - p_w).norm(), 1e-6);
  }
  // Too few solved views: `solved` waits, `solved_then_all` takes every view (here exact ones).
  const std::vector<TriangulationView> exact = exactViews(p_w, 8, 0.01, 0.05);
  EXPECT_EQ(triangulateTrajectory(exact, 3, TriangulationViews::kSolved, 5, options).failure,
            TriangulationFailure::kTooFewViews);
  const TriangulationResult fallback = triangulateTrajectory(exact, 3, TriangulationViews::kSolvedThenAll, 5, options);
  ASSERT_TRUE(fallback.p_w) << triangulationFailureName(fallback.failure);
  EXPECT_LT((*fallback.p_w - p_w).norm(), 1e-6);
  // Too little parallax among the solved views but enough among all (cameras 1 cm apart): the same.
  const std::vector<TriangulationView> slow = exactViews(p_w, 8, 0.01, 0.01);
  options.min_parallax_deg = 0.8;
  const TriangulationResult wide = triangulateTrajectory(slow, 8, TriangulationViews::kAll, 5, options);
  ASSERT_GT(wide.parallax_deg, 0.8);
  const TriangulationResult narrow = triangulateTrajectory(slow, 5, TriangulationViews::kSolved, 5, options);
  ASSERT_LT(narrow.parallax_deg, 0.8);
  EXPECT_EQ(narrow.failure, TriangulationFailure::kLowParallax);
  EXPECT_TRUE(triangulateTrajectory(slow, 5, TriangulationViews::kSolvedThenAll, 5, options).p_w);
  // The same when every view is solved; an unknown rule name is refused.
  EXPECT_TRUE(triangulateTrajectory(exact, 8, TriangulationViews::kSolved, 5, options).p_w);
  EXPECT_EQ(triangulationViewsFromName("solved_then_all"), TriangulationViews::kSolvedThenAll);
  EXPECT_THROW(triangulationViewsFromName("some"), std::invalid_argument);
}

TEST(Trajectory, ConstantVelocityExtensionIsInterpolatedExactly) {
  Trajectory trajectory;
  lie::Vec6 w;
  w << 0.5, -0.2, 0.1, 0.3, 0.1, -0.2;
  trajectory.add(0, lie::SE3(), w);
  trajectory.extendTo(50'000'000);
  trajectory.extendTo(100'000'000);
  for (int64_t t : {int64_t{0}, int64_t{13'000'000}, int64_t{50'000'000}, int64_t{77'000'000}, int64_t{100'000'000}}) {
    const lie::SE3 expected = lie::se3::exp(t * 1e-9 * w);
    EXPECT_LT((trajectory.pose(t).matrix() - expected.matrix()).norm(), 1e-12) << t;
    EXPECT_LT((trajectory.velocity(t) - w).norm(), 1e-12) << t;
  }
  EXPECT_THROW(trajectory.pose(-1), std::out_of_range);
  EXPECT_FALSE(trajectory.segment(100'000'001).has_value());
  ASSERT_TRUE(trajectory.segment(100'000'000).has_value());
  EXPECT_EQ(trajectory.segment(100'000'000)->first->t_ns, 50'000'000);
}

// r = A [x1; x2] − c, a linear factor on two Euclidean blocks of size 2.
class LinearFactor final : public ceres::SizedCostFunction<3, 2, 2> {
 public:
  LinearFactor(Eigen::Matrix<double, 3, 4> A, Eigen::Vector3d c) : A_(std::move(A)), c_(std::move(c)) {}
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    Eigen::Vector4d v(x[0][0], x[0][1], x[1][0], x[1][1]);
    Eigen::Map<Eigen::Vector3d> r(residuals);
    r = A_ * v - c_;
    for (int b = 0; b < 2; ++b) {
      if (jacobians == nullptr || jacobians[b] == nullptr) continue;
      Eigen::Map<Eigen::Matrix<double, 3, 2, Eigen::RowMajor>> J(jacobians[b]);
      J = A_.middleCols<2>(2 * b);
    }
    return true;
  }

 private:
  Eigen::Matrix<double, 3, 4> A_;
  Eigen::Vector3d c_;
};

/// Two linear factors r1 = A1[x1; x2] − c1 and r2 = A2[x1; x3] − c2 (Euclidean 2-vectors), and their
/// normal equations stacked over [x1; x2; x3] for the analytic marginalization of x1.
struct TwoLinearFactors {
  double x1[2] = {0.3, -0.1}, x2[2] = {1.0, 2.0}, x3[2] = {-0.5, 0.4};
  Eigen::Matrix<double, 3, 4> A1, A2;
  Eigen::Vector3d c1, c2;

  TwoLinearFactors(const Eigen::Matrix<double, 3, 4>& a1, const Eigen::Matrix<double, 3, 4>& a2, const Eigen::Vector3d& k1,
                   const Eigen::Vector3d& k2)
      : A1(a1), A2(a2), c1(k1), c2(k2) {}

  MarginalizationResult marginalizeX1() {
    FactorEntry f1{std::make_shared<LinearFactor>(A1, c1), nullptr, {x1, x2}};
    FactorEntry f2{std::make_shared<LinearFactor>(A2, c2), nullptr, {x1, x3}};
    const std::map<double*, BlockKind> kinds = {{x1, BlockKind::kEuclidean}, {x2, BlockKind::kEuclidean}, {x3, BlockKind::kEuclidean}};
    return marginalize({&f1, &f2}, {x1}, kinds);
  }

  /// H = JᵀJ and b = Jᵀr of both factors over [x1; x2; x3].
  void normalEquations(Eigen::Matrix<double, 6, 6>& H, Eigen::Matrix<double, 6, 1>& b) const {
    Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Zero();
    J.block<3, 2>(0, 0) = A1.leftCols<2>();
    J.block<3, 2>(0, 2) = A1.rightCols<2>();
    J.block<3, 2>(3, 0) = A2.leftCols<2>();
    J.block<3, 2>(3, 4) = A2.rightCols<2>();
    Eigen::Matrix<double, 6, 1> r;
    r << A1 * Eigen::Vector4d(x1[0], x1[1], x2[0], x2[1]) - c1, A2 * Eigen::Vector4d(x1[0], x1[1], x3[0], x3[1]) - c2;
    H = J.transpose() * J;
    b = J.transpose() * r;
  }

  /// The prior of `result` equals the Schur complement of x1 with H_mm⁺ = `H_mm_inverse`.
  void expectPriorIsTheReduction(const MarginalizationResult& result, const Eigen::Matrix2d& H_mm_inverse,
                                 const Eigen::Matrix<double, 6, 6>& H, const Eigen::Matrix<double, 6, 1>& b) const {
    const Eigen::Matrix4d H_star = H.bottomRightCorner<4, 4>() - H.bottomLeftCorner<4, 2>() * H_mm_inverse * H.topRightCorner<2, 4>();
    const Eigen::Vector4d b_star = b.tail<4>() - H.bottomLeftCorner<4, 2>() * H_mm_inverse * b.head<2>();
    const Eigen::MatrixXd& Jp = result.prior->jacobian();
    const Eigen::VectorXd& rp = result.prior->residual();
    EXPECT_LT((Jp.transpose() * Jp - H_star).norm(), 1e-9 * H_star.norm());
    EXPECT_LT((Jp.transpose() * rp - b_star).norm(), 1e-9 * (1 + b_star.norm()));
  }
};

TEST(Marginalization, SchurPriorEqualsTheAnalyticReductionOnALinearProblem) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0, 1);
  auto random = [&](auto m) {
    for (int i = 0; i < m.size(); ++i) m.data()[i] = n(rng);
    return m;
  };
  const Eigen::Matrix<double, 3, 4> A1 = random(Eigen::Matrix<double, 3, 4>()), A2 = random(Eigen::Matrix<double, 3, 4>());
  const Eigen::Vector3d c1 = random(Eigen::Vector3d()), c2 = random(Eigen::Vector3d());
  TwoLinearFactors problem(A1, A2, c1, c2);
  const MarginalizationResult result = problem.marginalizeX1();
  ASSERT_TRUE(result.prior);
  ASSERT_EQ(result.prior_blocks, (std::vector<double*>{problem.x2, problem.x3}));
  EXPECT_EQ(result.marginalized_dims, 2);
  EXPECT_EQ(result.kept_dims, 4);
  EXPECT_EQ(result.rank_mm, 2);
  // Analytic: stack both factors over [x1; x2; x3] and eliminate x1.
  Eigen::Matrix<double, 6, 6> H;
  Eigen::Matrix<double, 6, 1> b;
  problem.normalEquations(H, b);
  problem.expectPriorIsTheReduction(result, H.topLeftCorner<2, 2>().inverse(), H, b);
}

TEST(Marginalization, RankDeficientMarginalizedBlockIsEliminatedByItsPseudoInverse) {
  // x1's second coordinate is in no factor: H_mm has rank 1, so the Cholesky path is not taken and the
  // eigen pseudo-inverse eliminates the observed direction only.
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, 1);
  Eigen::Matrix<double, 3, 4> A1, A2;
  for (int i = 0; i < 12; ++i) A1(i) = n(rng), A2(i) = n(rng);
  A1.col(1).setZero();
  A2.col(1).setZero();
  TwoLinearFactors problem(A1, A2, Eigen::Vector3d(0.5, -1.0, 2.0), Eigen::Vector3d(1.0, 0.0, -0.5));
  const MarginalizationResult result = problem.marginalizeX1();
  ASSERT_TRUE(result.prior);
  EXPECT_EQ(result.rank_mm, 1);
  Eigen::Matrix<double, 6, 6> H;
  Eigen::Matrix<double, 6, 1> b;
  problem.normalEquations(H, b);
  Eigen::Matrix2d H_mm_pinv = Eigen::Matrix2d::Zero();
  H_mm_pinv(0, 0) = 1.0 / H(0, 0);
  problem.expectPriorIsTheReduction(result, H_mm_pinv, H, b);
}

TEST(Linearize, HuberCorrectionScalesAnOutlierResidual) {
  double x1[2] = {0, 0}, x2[2] = {0, 0};
  Eigen::Matrix<double, 3, 4> A = Eigen::Matrix<double, 3, 4>::Zero();
  A(0, 0) = 1;
  const Eigen::Vector3d c(-10, 0, 0);  // residual 10 with a Huber threshold of 1
  FactorEntry f{std::make_shared<LinearFactor>(A, c), std::make_shared<ceres::HuberLoss>(1.0), {x1, x2}};
  const LinearizedFactor lin = linearize(f, {BlockKind::kEuclidean, BlockKind::kEuclidean});
  ASSERT_TRUE(lin.valid);
  // Huber beyond the threshold: ρ' = 1/|r|, ρ'' < 0 ⇒ α = 0, r and J scaled by √ρ'.
  EXPECT_NEAR(lin.r(0), 10.0 / std::sqrt(10.0), 1e-12);
  EXPECT_NEAR(lin.J[0](0, 0), 1.0 / std::sqrt(10.0), 1e-12);
}

}  // namespace
}  // namespace asynevo::backend
