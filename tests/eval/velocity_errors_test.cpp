#include "asynevo/eval/velocity_errors.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "asynevo/eval/alignment.hpp"
#include "asynevo/eval/evaluate.hpp"
#include "eval_test_util.hpp"

namespace asynevo::eval {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

/// Exact helix twists every 50 ms from `t0_ms` to `t1_ms` (inclusive), each multiplied by `factor`
/// (linear part only).
std::vector<StampedTwist> helixTwists(int64_t t0_ms, int64_t t1_ms, double factor = 1.0) {
  std::vector<StampedTwist> twists;
  for (int64_t t = t0_ms; t <= t1_ms; t += 50) {
    StampedTwist tw = test::helixTwist(t * 1'000'000);
    tw.v_c *= factor;
    twists.push_back(tw);
  }
  return twists;
}

TEST(VelocityErrors, ExactTwistsGiveZeroErrorAndTheHelixSpeed) {
  const StampedTrajectory gt = test::helix(4000, 1'000'000);  // 1 kHz, 4 s
  const VelocityErrors v = computeVelocityErrors(gt, helixTwists(50, 3950), 1.0);
  EXPECT_EQ(v.est_twists, 79u);
  EXPECT_EQ(v.samples, 79u);
  ASSERT_EQ(v.linear_mps.num_samples, 79u);
  // Central differences over ±1 ms: O(h²) ≈ 1e-7.
  EXPECT_LT(v.linear_mps.max, 1e-5);
  EXPECT_LT(v.angular_dps.max, 1e-3);
  EXPECT_NEAR(v.mean_gt_speed_mps, std::sqrt(1.01), 1e-6);  // |ṗ| of the helix
  EXPECT_LT(v.linear_rmse_perc, 1e-3);
  EXPECT_GT(v.mean_gt_rate_dps, 50.0);  // about 1 rad/s
  EXPECT_NEAR(v.t_s.front(), 0.05, 1e-12);
}

TEST(VelocityErrors, TheScaleIsAppliedToTheLinearPartOnly) {
  const StampedTrajectory gt = test::helix(4000, 1'000'000);
  // An estimate in a map 4× the world: its linear velocity is 4× too, its angular velocity is not.
  const std::vector<StampedTwist> twists = helixTwists(50, 3950, 4.0);
  const VelocityErrors aligned = computeVelocityErrors(gt, twists, 0.25);
  EXPECT_DOUBLE_EQ(aligned.scale, 0.25);
  EXPECT_LT(aligned.linear_mps.max, 1e-5);
  EXPECT_LT(aligned.angular_dps.max, 1e-3);
  // Without the scale, the error is 3 v everywhere: 300 % of the (constant) speed.
  const VelocityErrors raw = computeVelocityErrors(gt, twists, 1.0);
  EXPECT_NEAR(raw.linear_mps.rmse, 3 * std::sqrt(1.01), 1e-4);
  EXPECT_NEAR(raw.linear_mps.min, 3 * std::sqrt(1.01), 1e-4);
  EXPECT_NEAR(raw.linear_rmse_perc, 300.0, 1e-2);
  EXPECT_LT(raw.angular_dps.max, 1e-3);
}

TEST(VelocityErrors, ConstantBiasesAreTheErrors) {
  const StampedTrajectory gt = test::helix(4000, 1'000'000);
  std::vector<StampedTwist> twists = helixTwists(50, 3950);
  for (StampedTwist& tw : twists) {
    tw.v_c += Eigen::Vector3d(0.0, 0.1, 0.0);
    tw.w_c += Eigen::Vector3d(0.0, 0.0, 0.01);
  }
  const VelocityErrors v = computeVelocityErrors(gt, twists, 1.0);
  EXPECT_NEAR(v.linear_mps.rmse, 0.1, 1e-5);
  EXPECT_NEAR(v.linear_mps.min, 0.1, 1e-5);
  EXPECT_NEAR(v.angular_dps.rmse, 0.01 * kRadToDeg, 1e-3);
  EXPECT_NEAR(v.linear_rmse_perc, 10.0 / std::sqrt(1.01), 1e-3);
}

TEST(VelocityErrors, TheDirectionOfTravelIsScaleFreeAndCatchesAnEstimateMovingBackwards) {
  const StampedTrajectory gt = test::helix(4000, 1'000'000);
  // A map 4x the world (or 1/4): the direction does not depend on the scale.
  const VelocityErrors scaled = computeVelocityErrors(gt, helixTwists(50, 3950, 4.0), 1.0);
  ASSERT_EQ(scaled.direction_deg.num_samples, 79u);  // constant speed: every sample is scored
  EXPECT_LT(scaled.direction_deg.max, 1e-3);
  EXPECT_EQ(scaled.reversed_fraction, 0.0);
  // The second half travels backwards (a depth-inverted map moves the camera the other way).
  std::vector<StampedTwist> twists = helixTwists(50, 3950);
  for (StampedTwist& tw : twists) {
    if (tw.t_ns >= 2'000'000'000) tw.v_c = -tw.v_c;
  }
  const VelocityErrors v = computeVelocityErrors(gt, twists, 1.0);
  EXPECT_NEAR(v.reversed_fraction, 40.0 / 79.0, 1e-12);  // 2.00 .. 3.95 s: 40 of 79 twists
  EXPECT_NEAR(v.direction_deg.max, 180.0, 1e-3);
  EXPECT_LT(v.direction_deg.min, 1e-3);
}

TEST(VelocityErrors, TheDirectionIsNotScoredNearAStop) {
  // Back and forth along x, p = sin(t): the speed |cos t| passes through 0 at t = pi/2, 3pi/2.
  StampedTrajectory gt;
  for (int64_t k = 0; k <= 6000; ++k) {
    StampedPose pose;
    pose.t_ns = k * 1'000'000;
    pose.p_w_c = Eigen::Vector3d(std::sin(k * 1e-3), 0.0, 0.0);
    gt.push_back(pose);
  }
  std::vector<StampedTwist> twists;
  std::size_t slow = 0;
  for (int64_t t_ms = 50; t_ms <= 5950; t_ms += 50) {
    StampedTwist tw;
    tw.t_ns = t_ms * 1'000'000;
    const double v = std::cos(t_ms * 1e-3);
    // Where the camera nearly stops, the estimate points the wrong way: not scored.
    const bool near_stop = std::abs(v) < 0.1;
    slow += near_stop;
    tw.v_c = Eigen::Vector3d(near_stop ? -v : v, 0.0, 0.0);
    twists.push_back(tw);
  }
  ASSERT_GT(slow, 0u);
  const VelocityErrors r = computeVelocityErrors(gt, twists, 1.0);
  EXPECT_EQ(r.samples, twists.size());
  // The mean of |cos| over [0, 6] is about 0.64: samples below a quarter of it are left out.
  EXPECT_LT(r.direction_deg.num_samples, twists.size() - slow + 1);
  EXPECT_GT(r.direction_deg.num_samples, twists.size() / 2);
  EXPECT_EQ(r.reversed_fraction, 0.0);
  EXPECT_LT(r.direction_deg.max, 1e-2);
}

TEST(VelocityErrors, TwistsOutsideTheGroundTruthOrInAHoleAreLeftOut) {
  // 1 kHz for 4 s without the poses strictly between 1.5 s and 2.0 s (a 0.5 s hole).
  StampedTrajectory gt;
  for (const StampedPose& pose : test::helix(4000, 1'000'000)) {
    if (pose.t_ns <= 1'500'000'000 || pose.t_ns >= 2'000'000'000) gt.push_back(pose);
  }
  const VelocityErrors v = computeVelocityErrors(gt, helixTwists(-200, 4200), 1.0);
  EXPECT_EQ(v.est_twists, 89u);
  // Ground-truth velocities exist at 1…1499 ms and 2001…3998 ms (poses with both neighbours within
  // 0.1 s): twists at 50…1450 ms (29) and 2050…3950 ms (39).
  EXPECT_EQ(v.samples, 68u);
  EXPECT_LT(v.linear_mps.max, 1e-5);
  // A ground-truth gap of 0.5 s is within a gap limit of 0.6 s: every twist from 1 ms on is covered,
  // but the velocity across the hole is a chord's, not the helix's.
  const VelocityErrors wide = computeVelocityErrors(gt, helixTwists(-200, 4200), 1.0, 600'000'000);
  EXPECT_EQ(wide.samples, 79u);
  EXPECT_GT(wide.linear_mps.max, 0.01);
}

TEST(VelocityErrors, NoSampleGivesEmptyStatisticsAndBadInputThrows) {
  const StampedTrajectory gt = test::helix(100, 1'000'000);
  const VelocityErrors none = computeVelocityErrors(gt, helixTwists(1000, 2000), 1.0);
  EXPECT_EQ(none.samples, 0u);
  EXPECT_EQ(none.linear_mps.num_samples, 0u);
  EXPECT_TRUE(std::isnan(none.linear_rmse_perc));
  EXPECT_THROW(computeVelocityErrors(gt, {}, 0.0), EvalError);
  EXPECT_THROW(computeVelocityErrors(gt, {}, std::nan("")), EvalError);
  EXPECT_THROW(computeVelocityErrors(gt, {}, 1.0, 0), EvalError);
  StampedTrajectory unsorted = gt;
  std::swap(unsorted[10], unsorted[11]);
  EXPECT_THROW(computeVelocityErrors(unsorted, {}, 1.0), EvalError);
}

TEST(VelocityErrors, EvaluationAppliesTheSim3ScaleAndWarnsAboutUncoveredTwists) {
  const StampedTrajectory gt = test::helix(4000, 1'000'000);
  // The estimate is the ground truth in a world twice as large, rotated and moved: scale 0.5.
  StampedTrajectory est;
  for (std::size_t i = 0; i < gt.size(); i += 50) est.push_back(gt[i]);
  est = test::transformed(est, 2.0, Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY())),
                          Eigen::Vector3d(-1, 4, 2));
  EvalResult r = evaluate(gt, est, EvalOptions{});
  ASSERT_NEAR(r.alignment.scale, 0.5, 1e-9);
  EXPECT_FALSE(r.velocity.has_value());
  addVelocityErrors(r, gt, helixTwists(50, 4200, 2.0), EvalOptions{}, "run/velocities.txt");
  ASSERT_TRUE(r.velocity.has_value());
  EXPECT_DOUBLE_EQ(r.velocity->scale, r.alignment.scale);
  EXPECT_EQ(r.velocity->samples, 79u);
  EXPECT_LT(r.velocity->linear_mps.max, 1e-5);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("run/velocities.txt: 5 of 84 twists have no ground-truth velocity"),
            std::string::npos)
      << r.warnings.back();
}

}  // namespace
}  // namespace asynevo::eval
