// Segmented evaluation (segments.hpp): each segment aligned on its own, errors pooled, coverage.
#include "asynevo/eval/segments.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "asynevo/core/error.hpp"
#include "eval_test_util.hpp"

namespace asynevo::eval {
namespace {

namespace fs = std::filesystem;

std::string writeFile(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "asynevo_segments_test";
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

StampedTrajectory slice(const StampedTrajectory& t, std::size_t from, std::size_t to) {
  return StampedTrajectory(t.begin() + static_cast<std::ptrdiff_t>(from), t.begin() + static_cast<std::ptrdiff_t>(to));
}

EstimateSegment segmentOf(const StampedTrajectory& part, int index, const std::string& ended_by) {
  return {index, part.front().t_ns, part.back().t_ns, part.size(), ended_by};
}

TEST(ReadSegments, ReadsTheRunsFormat) {
  const auto path = writeFile("ok.txt",
                              "# segments of the estimate\n# index start_s end_s knots ended_by\n"
                              "0 0.250000000 5.100000000 98 event_gap\n\n"
                              "1 5.600000000 10.000000000 89 end_of_stream\n");
  const auto segments = readSegments(path);
  ASSERT_EQ(segments.size(), 2u);
  EXPECT_EQ(segments[0].t0_ns, 250'000'000);
  EXPECT_EQ(segments[0].t1_ns, 5'100'000'000);
  EXPECT_EQ(segments[0].knots, 98u);
  EXPECT_EQ(segments[0].ended_by, "event_gap");
  EXPECT_EQ(segments[1].index, 1);
  EXPECT_EQ(segments[1].ended_by, "end_of_stream");
}

TEST(ReadSegments, BadLinesAreNamedWithFileAndLine) {
  const auto expectError = [](const std::string& name, const std::string& text, const std::string& where) {
    const auto path = writeFile(name, text);
    try {
      readSegments(path);
      ADD_FAILURE() << "no error for " << name;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path + where), std::string::npos) << e.what();
    }
  };
  expectError("fields.txt", "# header\n0 0.1 0.2 3\n", ":2:");
  expectError("extra.txt", "0 0.1 0.2 3 end_of_stream extra\n", ":1:");
  expectError("reversed.txt", "0 0.5 0.2 3 event_gap\n", ":1:");
  expectError("nan.txt", "0 nan 0.2 3 event_gap\n", ":1:");
  expectError("overlap.txt", "0 0.1 0.5 3 event_gap\n1 0.4 0.9 3 end_of_stream\n", ":2:");
  expectError("empty.txt", "# only a comment\n", "");
  EXPECT_THROW(readSegments(writeFile("dir", "") + ".missing"), InputError);
}

TEST(SegmentsBesideEstimate, FindsTheRunsFile) {
  const auto est = writeFile("stamped_traj_estimate.txt", "");
  fs::remove(fs::path(est).parent_path() / "segments.txt");
  EXPECT_EQ(segmentsBesideEstimate(est), "");
  const auto segments = writeFile("segments.txt", "0 0 1 2 end_of_stream\n");
  EXPECT_EQ(segmentsBesideEstimate(est), segments);
}

TEST(EvaluateSegmented, AlignsEachSegmentOnItsOwn) {
  const StampedTrajectory gt = test::helix(1000);
  // Two pieces of the estimate, each in its own frame and scale (a new map after a tracking loss),
  // with a gap of 0.5 s between them.
  const StampedTrajectory a = test::transformed(slice(gt, 0, 400), 2.0,
                                                Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
                                                Eigen::Vector3d(1, 2, 3));
  const StampedTrajectory b = test::transformed(slice(gt, 450, 1000), 0.5,
                                                Eigen::Quaterniond(Eigen::AngleAxisd(-1.0, Eigen::Vector3d::UnitZ())),
                                                Eigen::Vector3d(-4, 0, 1));
  StampedTrajectory est = a;
  est.insert(est.end(), b.begin(), b.end());
  const std::vector<EstimateSegment> segments = {segmentOf(a, 0, "event_gap"), segmentOf(b, 1, "end_of_stream")};

  const EvalResult r = evaluateSegmented(gt, est, segments, EvalOptions{});
  EXPECT_LT(r.ate.trans.rmse, 1e-9);
  EXPECT_LT(r.ate.rot.rmse, 1e-6);
  ASSERT_EQ(r.segments.size(), 2u);
  EXPECT_NEAR(r.segments[0].alignment.scale, 0.5, 1e-9);
  EXPECT_NEAR(r.segments[1].alignment.scale, 2.0, 1e-9);
  EXPECT_EQ(r.segments[0].ended_by, "event_gap");
  EXPECT_TRUE(r.segments[1].scored);
  EXPECT_EQ(r.matched, est.size());
  EXPECT_NEAR(*r.coverage, (399.0 + 549.0) / 999.0, 1e-9);
  // Relative errors: exact within each segment, none across the gap.
  ASSERT_FALSE(r.relative.empty());
  EXPECT_GT(r.relative[0].trans_m.size(), 0u);
  EXPECT_LT(r.relative[0].trans.max, 1e-9);
  for (const RelativeErrors& e : r.relative) {
    for (std::size_t k = 0; k < e.start.size(); ++k) {
      const bool start_in_a = e.start[k] < a.size(), end_in_a = e.end[k] < a.size();
      EXPECT_EQ(start_in_a, end_in_a) << "a sub-trajectory crosses the gap at length " << e.length_m;
    }
  }
  // As one piece, the same estimate has no good alignment.
  EXPECT_GT(evaluate(gt, est, EvalOptions{}).ate.trans.rmse, 0.1);
}

TEST(EvaluateSegmented, ScalesEachSegmentsVelocitiesByItsOwnScale) {
  const StampedTrajectory gt = test::helix(1000);
  const StampedTrajectory a = test::transformed(slice(gt, 0, 500), 2.0, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
  const StampedTrajectory b = test::transformed(slice(gt, 500, 1000), 0.25, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
  StampedTrajectory est = a;
  est.insert(est.end(), b.begin(), b.end());
  std::vector<StampedTwist> twists;
  for (const StampedPose& p : est) {
    StampedTwist w = test::helixTwist(p.t_ns);
    w.v_c *= p.t_ns < b.front().t_ns ? 2.0 : 0.25;  // the map's own units
    twists.push_back(w);
  }
  const EvalResult r = evaluateSegmented(gt, est, {segmentOf(a, 0, "depth"), segmentOf(b, 1, "end_of_stream")},
                                         EvalOptions{}, &twists);
  ASSERT_TRUE(r.velocity.has_value());
  EXPECT_GT(r.velocity->samples, 900u);
  EXPECT_LT(r.velocity->linear_rmse_perc, 2.0);
}

TEST(EvaluateSegmented, OneSegmentIsThePlainEvaluationWithCoverage) {
  const StampedTrajectory gt = test::helix(1000);
  const StampedTrajectory est = test::transformed(slice(gt, 100, 900), 3.0, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
  const EvalResult plain = evaluate(gt, est, EvalOptions{});
  const EvalResult one = evaluateSegmented(gt, est, {segmentOf(est, 0, "end_of_stream")}, EvalOptions{});
  EXPECT_EQ(one.ate.trans.rmse, plain.ate.trans.rmse);
  EXPECT_EQ(one.alignment.scale, plain.alignment.scale);
  ASSERT_EQ(one.relative.size(), plain.relative.size());
  EXPECT_EQ(one.pooled_trans.rmse, plain.pooled_trans.rmse);
  EXPECT_NEAR(*one.coverage, 799.0 / 999.0, 1e-9);
  EXPECT_FALSE(plain.coverage.has_value());
}

TEST(EvaluateSegmented, APoseOutsideEverySegmentIsAnError) {
  const StampedTrajectory gt = test::helix(1000);
  const StampedTrajectory est = slice(gt, 0, 600);
  const std::vector<EstimateSegment> segments = {segmentOf(slice(gt, 0, 200), 0, "event_gap"),
                                                 segmentOf(slice(gt, 300, 600), 1, "end_of_stream")};
  try {
    evaluateSegmented(gt, est, segments, EvalOptions{});
    ADD_FAILURE() << "no error";
  } catch (const EvalError& e) {
    EXPECT_NE(std::string(e.what()).find("estimate pose 200 (t = 2.000000 s) lies in no segment"), std::string::npos)
        << e.what();
  }
}

TEST(EvaluateSegmented, ASegmentTooShortToAlignIsListedNotScored) {
  const StampedTrajectory gt = test::helix(1000);
  const StampedTrajectory a = slice(gt, 0, 2);  // two poses: no Sim(3)
  const StampedTrajectory b = test::transformed(slice(gt, 100, 1000), 2.0, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
  StampedTrajectory est = a;
  est.insert(est.end(), b.begin(), b.end());
  const EvalResult r = evaluateSegmented(gt, est, {segmentOf(a, 0, "residual"), segmentOf(b, 1, "end_of_stream")},
                                         EvalOptions{});
  ASSERT_EQ(r.segments.size(), 2u);
  EXPECT_FALSE(r.segments[0].scored);
  EXPECT_FALSE(r.segments[0].note.empty());
  EXPECT_TRUE(r.segments[1].scored);
  EXPECT_LT(r.ate.trans.rmse, 1e-9);
  EXPECT_EQ(r.matched, b.size());
  bool warned = false;
  for (const std::string& w : r.warnings) warned |= w.find("segment 0") != std::string::npos;
  EXPECT_TRUE(warned);
}

}  // namespace
}  // namespace asynevo::eval
