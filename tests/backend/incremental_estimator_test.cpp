#include "asynevo/backend/incremental_estimator.hpp"

#include <gtest/gtest.h>

#include "asynevo/eval/alignment.hpp"
#include "synthetic_scene.hpp"

namespace asynevo::backend {
namespace {

using testing::SyntheticScene;

struct RunOutput {
  std::vector<Knot> knots;
  std::vector<UpdateRecord> records;
  EstimatorStats stats;
};

RunOutput run(Estimator& estimator, const std::vector<TrackMeasurement>& measurements, double duration_s) {
  RunOutput r;
  std::size_t next = 0;
  for (int64_t t = 0; t <= std::llround(duration_s * 1e9); t += 1'000'000) {
    while (next < measurements.size() && measurements[next].t_ns <= t) estimator.addMeasurement(measurements[next++]);
    estimator.advanceTo(t);
    for (auto& k : estimator.takeFinalKnots()) r.knots.push_back(k);
    for (auto& u : estimator.takeUpdateRecords()) r.records.push_back(u);
  }
  estimator.finish();
  for (auto& k : estimator.takeFinalKnots()) r.knots.push_back(k);
  for (auto& u : estimator.takeUpdateRecords()) r.records.push_back(u);
  r.stats = estimator.stats();
  return r;
}

double ateRmse(const std::vector<Knot>& knots) {
  std::vector<Eigen::Vector3d> p_est, p_gt;
  std::vector<Eigen::Matrix3d> R_est, R_gt;
  for (const Knot& k : knots) {
    const lie::SE3 gt = SyntheticScene::pose(k.t_ns * 1e-9);
    p_est.push_back(k.T_w_c().translation());
    R_est.push_back(k.T_w_c().rotation());
    p_gt.push_back(gt.translation());
    R_gt.push_back(gt.rotation());
  }
  const eval::Similarity S = eval::alignTrajectory(p_est, R_est, p_gt, R_gt, eval::AlignType::kSim3);
  double sum = 0;
  for (std::size_t i = 0; i < p_est.size(); ++i) sum += (S.apply(p_est[i]) - p_gt[i]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(p_est.size()));
}

EstimatorOptions baseOptions() {
  EstimatorOptions options;
  options.focal_px = 200;
  options.config.init_min_parallax_px = 8;  // the synthetic camera moves slowly
  return options;
}

TEST(IncrementalEstimator, FullHistoryKeepsEveryKnotAndReoptimizesOnNewMeasurements) {
  const SyntheticScene scene(150);
  const auto measurements = scene.measurements(2.0, 0.01, 0.4, 0.3);
  IncrementalEstimator estimator(baseOptions(), IncrementalOptions{});
  EXPECT_STREQ(estimator.name(), "full-history-smoother");
  const RunOutput r = run(estimator, measurements, 2.0);
  ASSERT_TRUE(r.stats.initialized) << r.stats.init_last_failure;
  EXPECT_EQ(r.stats.marginalizations, 0u);
  // The window is the whole history: it grows by one knot per knot interval, up to all knots.
  EXPECT_EQ(static_cast<std::size_t>(r.stats.max_window_knots), r.knots.size());
  // Triggered by measurements between knots too: many more updates than knots.
  EXPECT_GT(r.stats.updates, 2 * r.knots.size());
  int growth_violations = 0;
  for (std::size_t i = 1; i < r.records.size(); ++i) growth_violations += r.records[i].window_knots < r.records[i - 1].window_knots;
  EXPECT_EQ(growth_violations, 0);
  EXPECT_LT(ateRmse(r.knots), 0.01);  // metres over a ~0.6 m path (measured ~3 mm)
}

TEST(IncrementalEstimator, FrozenHistoryHoldsOldKnotsConstant) {
  const SyntheticScene scene(150);
  const auto measurements = scene.measurements(2.0, 0.01, 0.4, 0.3);
  IncrementalOptions frozen;
  frozen.frozen = true;
  frozen.active_knots = 8;
  IncrementalEstimator estimator(baseOptions(), frozen);
  EXPECT_STREQ(estimator.name(), "full-history-smoother-frozen");
  const RunOutput r = run(estimator, measurements, 2.0);
  ASSERT_TRUE(r.stats.initialized) << r.stats.init_last_failure;
  EXPECT_EQ(r.stats.marginalizations, 0u);
  EXPECT_EQ(static_cast<std::size_t>(r.stats.max_window_knots), r.knots.size());
  EXPECT_LT(ateRmse(r.knots), 0.02);
}

}  // namespace
}  // namespace asynevo::backend
