#include "asynevo/backend/incremental_estimator.hpp"

#include <gtest/gtest.h>

#include "estimator_harness.hpp"

namespace asynevo::backend {
namespace {

using testing::SyntheticScene;

using RunOutput = testing::EstimatorRun;

RunOutput run(Estimator& estimator, const std::vector<TrackMeasurement>& measurements, double duration_s) {
  return testing::driveEstimator(estimator, measurements, duration_s);
}

double ateRmse(const std::vector<Knot>& knots) { return testing::accuracy(knots).ate_rmse; }

EstimatorOptions baseOptions() { return testing::syntheticSceneOptions(); }

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
