// Landmark rejoin (backend.landmark_rejoin_px): which landmark no longer measured a new trajectory extends
// (findRejoinLandmark), and the estimator doing it on re-detected corners.

#include <gtest/gtest.h>

#include <vector>

#include "asynevo/backend/landmark_rejoin.hpp"
#include "asynevo/backend/sliding_window_estimator.hpp"
#include "estimator_harness.hpp"

namespace asynevo::backend {
namespace {

constexpr double kFocal = 200.0;

/// Five views of the point p_w from a camera moving `step` m along x between them (identity rotation),
/// with the image point shifted by offset_px.
std::vector<TriangulationView> viewsOf(const Eigen::Vector3d& p_w, const Eigen::Vector2d& offset_px,
                                       double step = 0.02) {
  std::vector<TriangulationView> views;
  for (int i = 0; i < 5; ++i) {
    const lie::SE3 T_w_c(Eigen::Matrix3d::Identity(), Eigen::Vector3d(step * i, 0, 0));
    const Eigen::Vector3d p_c = T_w_c.inverse() * p_w;
    views.push_back({T_w_c, p_c.head<2>() / p_c.z() + offset_px / kFocal});
  }
  return views;
}

FeatureTrack landmarkAt(int64_t id, const Eigen::Vector3d& p_w, int64_t last_ns) {
  FeatureTrack track;
  track.id = id;
  track.observations.push_back({last_ns - 100'000'000, Eigen::Vector2d::Zero()});
  track.observations.push_back({last_ns, Eigen::Vector2d::Zero()});
  track.triangulated = true;
  Eigen::Map<Eigen::Vector3d>(track.p_w.data()) = p_w;
  return track;
}

RejoinOptions options(double px) {
  RejoinOptions o;
  o.max_error = px / kFocal;
  o.min_depth = 0.05;
  return o;
}

constexpr int64_t kFirstNs = 1'000'000'000;

TEST(LandmarkRejoin, TakesTheOneLandmarkThatFitsEveryView) {
  const Eigen::Vector3d p(0.3, -0.1, 2.0);
  TrackMap tracks;
  tracks[7] = landmarkAt(7, p, kFirstNs - 20'000'000);
  tracks[9] = landmarkAt(9, p + Eigen::Vector3d(0.2, 0, 0), kFirstNs - 20'000'000);  // 20 px away
  const RejoinMatch match = findRejoinLandmark(viewsOf(p, {1.0, -1.0}), kFirstNs, tracks, options(2));
  ASSERT_TRUE(match.key);
  EXPECT_EQ(*match.key, 7);
  EXPECT_EQ(match.candidates_fitting, 1);
}

TEST(LandmarkRejoin, NoneWhenAViewMissesByMoreThanTheBound) {
  const Eigen::Vector3d p(0.3, -0.1, 2.0);
  TrackMap tracks;
  tracks[7] = landmarkAt(7, p, kFirstNs - 20'000'000);
  auto views = viewsOf(p, {0, 0});
  views.back().xn.x() += 2.5 / kFocal;  // one view 2.5 px off
  EXPECT_FALSE(findRejoinLandmark(views, kFirstNs, tracks, options(2)).key);
  EXPECT_TRUE(findRejoinLandmark(views, kFirstNs, tracks, options(3)).key);
}

TEST(LandmarkRejoin, SkipsLandmarksLastMeasuredLongerAgoThanTheGap) {
  const Eigen::Vector3d p(0.3, -0.1, 2.0);
  TrackMap tracks;
  tracks[7] = landmarkAt(7, p, kFirstNs - 60'000'000);  // last measured 60 ms before
  RejoinOptions o = options(2);
  o.max_gap_ns = 50'000'000;
  EXPECT_FALSE(findRejoinLandmark(viewsOf(p, {0, 0}), kFirstNs, tracks, o).key);
  o.max_gap_ns = 60'000'000;
  EXPECT_TRUE(findRejoinLandmark(viewsOf(p, {0, 0}), kFirstNs, tracks, o).key);
}

TEST(LandmarkRejoin, NoneWhenTwoLandmarksFit) {
  const Eigen::Vector3d p(0.3, -0.1, 2.0);
  TrackMap tracks;
  tracks[7] = landmarkAt(7, p, kFirstNs - 20'000'000);
  tracks[8] = landmarkAt(8, p + Eigen::Vector3d(0.004, 0, 0), kFirstNs - 20'000'000);  // 0.4 px away
  const RejoinMatch match = findRejoinLandmark(viewsOf(p, {0, 0}), kFirstNs, tracks, options(2));
  EXPECT_FALSE(match.key);
  EXPECT_EQ(match.candidates_fitting, 2);
}

TEST(LandmarkRejoin, SkipsLandmarksStillMeasuredUntriangulatedOrBehindTheCamera) {
  const Eigen::Vector3d p(0.3, -0.1, 2.0);
  const auto views = viewsOf(p, {0, 0});
  TrackMap measured;
  measured[7] = landmarkAt(7, p, kFirstNs);  // measured at the new trajectory's first time: another point
  EXPECT_FALSE(findRejoinLandmark(views, kFirstNs, measured, options(2)).key);
  TrackMap untriangulated;
  untriangulated[7] = landmarkAt(7, p, kFirstNs - 20'000'000);
  untriangulated[7].triangulated = false;
  EXPECT_FALSE(findRejoinLandmark(views, kFirstNs, untriangulated, options(2)).key);
  // Seen from a camera at rest, the mirrored point projects exactly as the point does, but behind it.
  const auto still = viewsOf(p, {0, 0}, 0.0);
  TrackMap front, behind;
  front[7] = landmarkAt(7, p, kFirstNs - 20'000'000);
  behind[7] = landmarkAt(7, -p, kFirstNs - 20'000'000);
  EXPECT_TRUE(findRejoinLandmark(still, kFirstNs, front, options(2)).key);
  EXPECT_FALSE(findRejoinLandmark(still, kFirstNs, behind, options(2)).key);
  TrackMap off;
  off[7] = landmarkAt(7, p, kFirstNs - 20'000'000);
  EXPECT_FALSE(findRejoinLandmark(views, kFirstNs, off, options(0)).key);
}

// The synthetic scene re-detects every landmark as a new feature every 0.4 s, at the point where its
// previous feature ended: each new trajectory is the same scene point seen again.
TEST(LandmarkRejoin, ReDetectedCornersExtendTheirLandmarks) {
  const testing::SyntheticScene scene(150);
  constexpr double kDuration = 4.0;
  const auto measurements = scene.measurements(kDuration, 0.01, 0.4, 0.3);
  auto run = [&](double rejoin_px) {
    EstimatorOptions options = testing::syntheticSceneOptions();
    options.config.landmark_rejoin_px = rejoin_px;
    SlidingWindowEstimator estimator(options);
    return testing::driveEstimator(estimator, measurements, kDuration);
  };
  const testing::EstimatorRun off = run(0), on = run(2);
  ASSERT_TRUE(off.stats.initialized) << off.stats.init_last_failure;
  ASSERT_TRUE(on.stats.initialized) << on.stats.init_last_failure;
  EXPECT_EQ(off.stats.landmarks_rejoined, 0u);
  // After the start most re-detections find their landmark still in the window.
  EXPECT_GE(on.stats.landmarks_rejoined, on.stats.landmarks_created / 2)
      << "rejoined " << on.stats.landmarks_rejoined << ", created " << on.stats.landmarks_created;
  EXPECT_LT(on.stats.landmarks_created, off.stats.landmarks_created);
  EXPECT_EQ(on.stats.measurements_of_superseded_features, 0u);  // no old feature measures again
  const double ate_on = testing::accuracy(on.knots).ate_rmse, ate_off = testing::accuracy(off.knots).ate_rmse;
  // The points live on through the re-detections, and the map holds its scale (0.0077 -> 0.0057 m when
  // written).
  EXPECT_LT(ate_on, 0.8 * ate_off) << "ATE with rejoins " << ate_on << ", without " << ate_off;
}

}  // namespace
}  // namespace asynevo::backend
