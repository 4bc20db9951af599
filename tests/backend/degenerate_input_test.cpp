// Numerical safety (docs/reliability.md): degenerate configurations — every feature on one line, a
// camera that never moves, a single landmark, the map collapsing to one landmark after the start,
// non-finite measurements — never crash the estimator and never make it emit a non-finite estimate.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "asynevo/backend/sliding_window_estimator.hpp"
#include "estimator_harness.hpp"

namespace asynevo::backend {
namespace {

using testing::SyntheticScene;

void expectFinite(const testing::EstimatorRun& run) {
  for (std::size_t i = 0; i < run.knots.size(); ++i) {
    ASSERT_TRUE(run.knots[i].T_w_c().matrix().allFinite()) << "knot " << i;
    ASSERT_TRUE(run.knots[i].twist().allFinite()) << "knot " << i;
  }
  for (const UpdateRecord& r : run.records) ASSERT_TRUE(std::isfinite(r.final_cost));
}

testing::EstimatorRun runOn(const SyntheticScene& scene, double duration_s, double life_s = 0.4) {
  const auto ms = scene.measurements(duration_s, 0.01, life_s, 0.3);
  SlidingWindowEstimator estimator(testing::syntheticSceneOptions());
  return testing::driveEstimator(estimator, ms, duration_s);
}

TEST(DegenerateInput, EveryFeatureOnOneLine) {
  // 60 points on one 3-D line in front of the camera: every image is a line of points, so no pose is
  // determined by a two-view or multi-view fit (rotation about the line is free).
  SyntheticScene scene(0);
  for (int i = 0; i < 60; ++i) {
    const double s = -1.0 + 2.0 * i / 59.0;
    scene.landmarks.emplace_back(2.0 * s, 0.3 * s, 4.0 + 0.5 * s);
  }
  const auto run = runOn(scene, 3.0);
  expectFinite(run);
  EXPECT_GT(run.stats.init_attempts, 0u);
  if (!run.stats.initialized) {
    EXPECT_FALSE(run.stats.init_last_failure.empty());
  }
}

TEST(DegenerateInput, ACameraThatNeverMovesNeverStartsAndSaysWhy) {
  SyntheticScene scene(150);
  scene.trajectory = [](double) { return SyntheticScene::pose(0.0); };
  const auto run = runOn(scene, 3.0);
  expectFinite(run);
  EXPECT_FALSE(run.stats.initialized);
  EXPECT_TRUE(run.knots.empty());
  EXPECT_GT(run.stats.init_attempts, 50u);
  // Every attempt stops before a pose: for want of image motion (or of features before tracks exist).
  const auto& rejections = run.stats.init_rejections;
  EXPECT_GT(rejections[static_cast<int>(InitRejection::Motion)], 0u);
  EXPECT_EQ(rejections[static_cast<int>(InitRejection::Landmarks)], 0u);
  EXPECT_NE(run.stats.init_last_failure.find("median motion"), std::string::npos) << run.stats.init_last_failure;
}

TEST(DegenerateInput, OneLandmarkNeverStarts) {
  SyntheticScene scene(0);
  scene.landmarks.emplace_back(0.2, 0.1, 4.0);
  const auto run = runOn(scene, 2.0);
  expectFinite(run);
  EXPECT_FALSE(run.stats.initialized);
  EXPECT_EQ(run.stats.init_rejections[static_cast<int>(InitRejection::Features)], run.stats.init_attempts);
}

TEST(DegenerateInput, TheMapCollapsingToOneLandmarkAfterTheStart) {
  // 150 landmarks for 1.5 s, then all but one leave view: the window runs on the prior and one track.
  SyntheticScene scene(150);
  const Eigen::Vector3d survivor = scene.landmarks.front();
  auto ms = scene.measurements(1.5, 0.01, 0.4, 0.3);
  SyntheticScene late(0);
  late.landmarks.push_back(survivor);
  for (TrackMeasurement m : late.measurements(3.0, 0.01, 3.0, 0.3)) {
    if (m.t_ns < 1'500'000'000) continue;
    m.feature_id += 1'000'000;  // a new track
    ms.push_back(m);
  }
  SlidingWindowEstimator estimator(testing::syntheticSceneOptions());
  const auto run = testing::driveEstimator(estimator, ms, 3.0);
  ASSERT_TRUE(run.stats.initialized) << run.stats.init_last_failure;
  expectFinite(run);
  ASSERT_FALSE(run.knots.empty());
  EXPECT_GT(run.knots.back().t_ns, 2'500'000'000) << "the estimate goes on through the collapse";
}

TEST(DegenerateInput, NonFiniteMeasurementsAreCountedAndDropped) {
  const SyntheticScene scene(150);
  auto ms = scene.measurements(2.0, 0.01, 0.4, 0.3);
  std::size_t injected = 0;
  for (std::size_t i = 0; i < ms.size(); i += 7) {
    ms[i].xn = i % 2 ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
    ++injected;
  }
  SlidingWindowEstimator estimator(testing::syntheticSceneOptions());
  const auto run = testing::driveEstimator(estimator, ms, 2.0);
  EXPECT_EQ(run.stats.measurements_non_finite, injected);
  ASSERT_TRUE(run.stats.initialized) << run.stats.init_last_failure;
  expectFinite(run);
}

}  // namespace
}  // namespace asynevo::backend
