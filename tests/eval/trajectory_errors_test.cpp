#include "asynevo/eval/trajectory_errors.hpp"

#include <gtest/gtest.h>

#include "asynevo/eval/evaluate.hpp"
#include "eval_test_util.hpp"

namespace asynevo::eval {
namespace {

using test::helix;
using test::line;
using test::transformed;

TEST(Distances, CumulativePathLength) {
  const auto d = distancesFromStart({{0, 0, 0}, {3, 4, 0}, {3, 4, 0}, {3, 4, 2}});
  EXPECT_EQ(d, (std::vector<double>{0, 5, 5, 7}));
}

TEST(ComparisonIndices, ClosestWithinToleranceLikeRpg) {
  const std::vector<double> d = {0, 1, 2, 3, 4, 5};
  EXPECT_EQ(comparisonIndices(d, 2.0, 0.4), (std::vector<std::size_t>{2, 3, 4, 5}));
  // Closest, not first reaching: from 0, target 1.5: 1 and 2 are both 0.5 away -> the first (1).
  EXPECT_EQ(comparisonIndices({0, 1, 2}, 1.5, 0.6), (std::vector<std::size_t>{1, 2}));
  // Tolerance is strict: 0.5 away with tolerance 0.5 is not accepted.
  EXPECT_EQ(comparisonIndices({0, 1, 2}, 1.5, 0.5), (std::vector<std::size_t>{}));
  // Equal distances (standing still): the first index holding the closest value. Start 1 (0.5 m)
  // has nothing within 0.2 of 1.5 m and is left out.
  EXPECT_EQ(comparisonIndices({0, 0.5, 1, 1, 1, 2}, 1.0, 0.2), (std::vector<std::size_t>{2, 5, 5, 5}));
}

TEST(ComparisonIndices, MatchesTheForwardScanDefinition) {
  // Irregular distances with repeats; compare with rpg's O(n²) scan written out.
  std::vector<double> d = {0};
  for (int i = 1; i < 400; ++i) d.push_back(d.back() + ((i * 37) % 11) * 0.013);
  for (double length : {0.05, 0.3, 1.0, 2.5}) {
    const double tol = 0.2 * length;
    std::vector<std::size_t> brute;
    for (std::size_t idx = 0; idx < d.size(); ++idx) {
      long best = -1;
      double err = tol;
      for (std::size_t i = idx; i < d.size(); ++i) {
        if (std::fabs(d[i] - (d[idx] + length)) < err) {
          best = static_cast<long>(i);
          err = std::fabs(d[i] - (d[idx] + length));
        }
      }
      if (best != -1) brute.push_back(static_cast<std::size_t>(best));
    }
    EXPECT_EQ(comparisonIndices(d, length, tol), brute) << length;
  }
}

TEST(LengthsFromPercentages, TruncatedToTwoDecimals) {
  EXPECT_EQ(lengthsFromPercentages(12.3456, {0.1, 0.2, 0.3, 0.4, 0.5}),
            (std::vector<double>{1.23, 2.46, 3.70, 4.93, 6.17}));
  EXPECT_EQ(lengthsFromPercentages(0.049, {0.1}), (std::vector<double>{0.0}));
}

PosePairs pairsOf(const StampedTrajectory& gt, const StampedTrajectory& est) {
  PosePairs p;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    p.p_gt.push_back(gt[i].p_w_c);
    p.R_gt.push_back(gt[i].q_w_c.toRotationMatrix());
    p.p_est.push_back(est[i].p_w_c);
    p.R_est.push_back(est[i].q_w_c.toRotationMatrix());
    p.t_gt_ns.push_back(gt[i].t_ns);
  }
  return p;
}

TEST(RelativeErrors, RpgStartIndexingQuirk) {
  // Starts 0, 2, 3 have ends (1, 3, 4); start 1 has none. rpg pairs the k-th end with start k.
  const std::vector<double> d = {0, 1, 10, 11, 12};
  StampedTrajectory gt;
  for (double x : d) {
    StampedPose pose;
    pose.p_w_c = Eigen::Vector3d(x, 0, 0);
    gt.push_back(pose);
  }
  const PosePairs pairs = pairsOf(gt, gt);
  const RelativeErrors rpg = computeRelativeErrors(pairs, d, 1.0, 1.0);
  EXPECT_EQ(rpg.start, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(rpg.end, (std::vector<std::size_t>{1, 3, 4}));
  EXPECT_EQ(rpg.shifted_starts, 2u);
  RelativeErrorOptions fixed;
  fixed.rpg_start_indexing = false;
  const RelativeErrors own = computeRelativeErrors(pairs, d, 1.0, 1.0, fixed);
  EXPECT_EQ(own.start, (std::vector<std::size_t>{0, 2, 3}));
  EXPECT_EQ(own.shifted_starts, 0u);
  for (double e : own.trans_m) EXPECT_NEAR(e, 0.0, 1e-12);
}

TEST(RelativeErrors, TooFewSubTrajectories) {
  const StampedTrajectory gt = line(3, 10'000'000, 1.0);  // 2 cm of path
  const PosePairs pairs = pairsOf(gt, gt);
  const RelativeErrors rel = computeRelativeErrors(pairs, distancesFromStart(pairs.p_gt), 0.02, 1.0);
  EXPECT_TRUE(rel.too_few);  // only one start reaches 2 cm
  EXPECT_TRUE(rel.trans_m.empty());
}

TEST(RelativeErrors, KnownTranslationDrift) {
  // Ground truth moves 1 m/s along x; the estimate moves 1.1 m/s (10 % drift), no alignment.
  const StampedTrajectory gt = line(1001, 10'000'000, 1.0);  // 10 m, 1 cm steps
  StampedTrajectory est = gt;
  for (auto& pose : est) pose.p_w_c *= 1.1;
  const PosePairs pairs = pairsOf(gt, est);
  const RelativeErrors rel = computeRelativeErrors(pairs, distancesFromStart(pairs.p_gt), 2.0, 1.0);
  // Starts 0 … 8.39 m: from 8.01 m on, the end is the last pose (10 m), within the 0.4 m tolerance.
  ASSERT_EQ(rel.trans_m.size(), 840u);
  for (std::size_t k = 0; k < rel.trans_m.size(); ++k) {
    EXPECT_EQ(rel.start[k], k);
    EXPECT_EQ(rel.end[k], std::min<std::size_t>(k + 200, 1000));
    const double travelled = 0.01 * static_cast<double>(rel.end[k] - k);
    EXPECT_NEAR(rel.trans_m[k], 0.1 * travelled, 1e-9);
    EXPECT_NEAR(rel.trans_perc[k], 0.1 * travelled / 2.0 * 100.0, 1e-7);  // % of the nominal length
    EXPECT_NEAR(rel.rot_deg[k], 0.0, 1e-6);
  }
  EXPECT_NEAR(rel.trans.median, 0.2, 1e-9);
  // With the scale an alignment would find (1/1.1) the drift disappears.
  const RelativeErrors scaled = computeRelativeErrors(pairs, distancesFromStart(pairs.p_gt), 2.0, 1.0 / 1.1);
  EXPECT_NEAR(scaled.trans.max, 0.0, 1e-9);
}

TEST(RelativeErrors, KnownRotationDrift) {
  // The estimate's yaw drifts by 2 deg per second relative to the ground truth (1 m/s): over 2 m
  // (2 s) the relative rotation error is 4 deg, all of it yaw.
  const StampedTrajectory gt = line(1001, 10'000'000, 1.0);
  StampedTrajectory est = gt;
  for (auto& pose : est) {
    const double yaw = 2.0 * M_PI / 180.0 * 1e-9 * static_cast<double>(pose.t_ns);
    pose.q_w_c = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    pose.p_w_c = gt[&pose - &est[0]].p_w_c;
  }
  const PosePairs pairs = pairsOf(gt, est);
  const RelativeErrors rel = computeRelativeErrors(pairs, distancesFromStart(pairs.p_gt), 2.0, 1.0);
  ASSERT_EQ(rel.rot_deg.size(), 840u);
  for (std::size_t k = 0; k < rel.rot_deg.size(); ++k) {
    const double seconds = 0.01 * static_cast<double>(rel.end[k] - rel.start[k]);
    EXPECT_NEAR(rel.rot_deg[k], 2.0 * seconds, 1e-9);
    EXPECT_NEAR(rel.yaw_deg[k], 2.0 * seconds, 1e-9);
    EXPECT_NEAR(rel.rot_deg_per_m[k], 2.0 * seconds / 2.0, 1e-9);
  }
  EXPECT_NEAR(rel.rot.median, 4.0, 1e-9);
  EXPECT_NEAR(rel.rot.max, 4.0, 1e-9);
  EXPECT_NEAR(rel.gravity.max, 0.0, 1e-9);
  // The rotated estimate's relative translation T_i⁻¹ T_j differs from the ground truth's.
  EXPECT_GT(rel.trans.mean, 0.0);
}

TEST(AbsoluteErrors, ConstantOffsetAndRotation) {
  const StampedTrajectory gt = helix(200);
  StampedTrajectory est = gt;
  const Eigen::Quaterniond body_rot(Eigen::AngleAxisd(5.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()));
  for (auto& pose : est) {
    pose.p_w_c += Eigen::Vector3d(0.1, 0.0, 0.0);
    pose.q_w_c = pose.q_w_c * body_rot;  // 5 deg about the camera's y axis
  }
  const AbsoluteErrors ate = computeAbsoluteErrors(pairsOf(gt, est), Similarity{});
  EXPECT_NEAR(ate.trans.rmse, 0.1, 1e-12);
  EXPECT_NEAR(ate.trans.min, 0.1, 1e-12);
  EXPECT_NEAR(ate.trans.std, 0.0, 1e-12);
  EXPECT_NEAR(ate.rot.mean, 5.0, 1e-9);
  EXPECT_NEAR(ate.rot.max, 5.0, 1e-9);
}

TEST(Evaluate, SimilarityTransformedCopyHasZeroError) {
  const StampedTrajectory gt = helix(1000);
  const Eigen::Quaterniond R(Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -1, 2).normalized()));
  // est = GT scaled by 2 and moved: the Sim(3) alignment undoes it exactly (scale 1/2).
  const StampedTrajectory est = transformed(gt, 2.0, R, Eigen::Vector3d(5, -3, 1));
  const EvalResult r = evaluate(gt, est, EvalOptions{});
  EXPECT_EQ(r.matched, 1000u);
  EXPECT_NEAR(r.alignment.scale, 0.5, 1e-12);
  EXPECT_LT(r.ate.trans.max, 1e-12);
  EXPECT_LT(r.ate.rot.max, 1e-5);  // arccos near 1 limits this to ~sqrt(eps)
  ASSERT_EQ(r.relative.size(), 5u);
  for (const RelativeErrors& rel : r.relative) {
    EXPECT_GT(rel.trans.num_samples, 100u);
    EXPECT_LT(rel.trans.max, 1e-12);
    EXPECT_LT(rel.rot.max, 1e-5);
  }
  // Lengths are 10 … 50 % of the GT path, truncated to cm.
  EXPECT_NEAR(r.relative[0].length_m, std::trunc(0.1 * r.gt_path_length_m * 100.0) / 100.0, 0.0);
  EXPECT_EQ(r.pooled_trans.num_samples, r.relative[0].trans.num_samples + r.relative[1].trans.num_samples +
                                            r.relative[2].trans.num_samples +
                                            r.relative[3].trans.num_samples +
                                            r.relative[4].trans.num_samples);
}

TEST(Evaluate, Se3AndPosYawAlignRigidCopies) {
  const StampedTrajectory gt = helix(500);
  EvalOptions options;
  options.align = AlignType::kSe3;
  const Eigen::Quaterniond R(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, 0, 1).normalized()));
  EvalResult r = evaluate(gt, transformed(gt, 1.0, R, Eigen::Vector3d(1, 2, 3)), options);
  EXPECT_LT(r.ate.trans.max, 1e-12);
  EXPECT_EQ(r.alignment.scale, 1.0);
  options.align = AlignType::kPosYaw;
  const Eigen::Quaterniond yaw(Eigen::AngleAxisd(-2.5, Eigen::Vector3d::UnitZ()));
  r = evaluate(gt, transformed(gt, 1.0, yaw, Eigen::Vector3d(1, 2, 3)), options);
  EXPECT_LT(r.ate.trans.max, 1e-12);
  options.align_frames = 1;  // first pose only
  r = evaluate(gt, transformed(gt, 1.0, yaw, Eigen::Vector3d(1, 2, 3)), options);
  EXPECT_LT(r.ate.trans.max, 1e-12);
}

TEST(Evaluate, ConstantOffsetWithoutAlignment) {
  const StampedTrajectory gt = helix(500);
  const StampedTrajectory est =
      transformed(gt, 1.0, Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0.3, 0.4));
  EvalOptions options;
  options.align = AlignType::kNone;
  const EvalResult r = evaluate(gt, est, options);
  EXPECT_NEAR(r.ate.trans.rmse, 0.5, 1e-12);
  EXPECT_NEAR(r.ate.trans.median, 0.5, 1e-12);
  for (const RelativeErrors& rel : r.relative) EXPECT_LT(rel.trans.max, 1e-12);  // offsets cancel
}

TEST(Evaluate, GivenLengthsInMetres) {
  const StampedTrajectory gt = line(1001, 10'000'000, 1.0);
  StampedTrajectory est = gt;
  for (auto& pose : est) pose.p_w_c *= 1.1;
  EvalOptions options;
  options.align = AlignType::kNone;
  options.rel_lengths_m = {1.0, 3.0};
  const EvalResult r = evaluate(gt, est, options);
  ASSERT_EQ(r.relative.size(), 2u);
  // Medians: the last starts end early (at the last pose, within the 20 % tolerance).
  EXPECT_NEAR(r.relative[0].trans.median, 0.1, 1e-9);
  EXPECT_NEAR(r.relative[1].trans.median, 0.3, 1e-9);
  EXPECT_NEAR(r.relative[1].trans.max, 0.3, 1e-9);
  EXPECT_NEAR(r.relative[1].trans_perc_stats.median, 10.0, 1e-7);
  EXPECT_NEAR(r.pooled_trans_perc.median, 10.0, 1e-7);
  EXPECT_EQ(r.relative[0].trans.num_samples, 920u);  // starts 0 … 9.19 m
  EXPECT_EQ(r.relative[1].trans.num_samples, 760u);  // starts 0 … 7.59 m
}

TEST(Evaluate, AssociatesDifferentRates) {
  // Ground truth at 200 Hz, estimate at 50 Hz offset by 1 ms: every estimate pose associates.
  const StampedTrajectory gt = helix(2000, 5'000'000);
  StampedTrajectory est = helix(500, 20'000'000, 1'000'000);
  const EvalResult r = evaluate(gt, est, EvalOptions{});
  EXPECT_EQ(r.matched, 500u);
  EXPECT_TRUE(r.warnings.empty());
  for (std::size_t k = 0; k < r.matches.size(); ++k) EXPECT_EQ(r.matches[k].gt, 4 * k);
}

TEST(Evaluate, BadInputIsExplained) {
  const StampedTrajectory gt = helix(100);
  // No overlap.
  const StampedTrajectory late = helix(100, 10'000'000, 100'000'000'000);
  try {
    evaluate(gt, late, EvalOptions{});
    ADD_FAILURE();
  } catch (const EvalError& e) {
    EXPECT_NE(std::string(e.what()).find("do not overlap"), std::string::npos) << e.what();
  }
  // Fewer than 3 associated poses.
  const StampedTrajectory two(gt.begin(), gt.begin() + 2);
  EXPECT_THROW(evaluate(gt, two, EvalOptions{}), EvalError);
  // Empty.
  EXPECT_THROW(evaluate(gt, StampedTrajectory{}, EvalOptions{}), EvalError);
  EXPECT_THROW(evaluate(StampedTrajectory{}, gt, EvalOptions{}), EvalError);
  // NaN in a pose.
  StampedTrajectory nan = gt;
  nan[5].p_w_c.y() = std::nan("");
  try {
    evaluate(gt, nan, EvalOptions{});
    ADD_FAILURE();
  } catch (const EvalError& e) {
    EXPECT_NE(std::string(e.what()).find("pose 5"), std::string::npos) << e.what();
  }
  // Options.
  EvalOptions options;
  options.align_frames = 0;
  EXPECT_THROW(evaluate(gt, gt, options), EvalError);
  options.align_frames = 1000;
  EXPECT_THROW(evaluate(gt, gt, options), EvalError);
  options = EvalOptions{};
  options.rel_lengths_m = {-1.0};
  EXPECT_THROW(evaluate(gt, gt, options), EvalError);
  // All estimate positions equal: no Sim(3) scale.
  StampedTrajectory still = gt;
  for (auto& pose : still) pose.p_w_c = Eigen::Vector3d(1, 1, 1);
  EXPECT_THROW(evaluate(gt, still, EvalOptions{}), EvalError);
}

}  // namespace
}  // namespace asynevo::eval
