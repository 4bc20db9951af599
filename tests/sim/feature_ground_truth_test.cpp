#include "asynevo/sim/feature_ground_truth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "asynevo/core/error.hpp"
#include "asynevo/sim/simulate.hpp"
#include "sim_test_util.hpp"

namespace asynevo::sim {
namespace {

using testing::TempDir;

TexturedPlane frontoParallel(const char* name, double z, double half) {
  TexturedPlane p;
  p.name = name;
  p.center_w = Eigen::Vector3d(0, 0, z);
  p.half_width = half;
  p.half_height = half;
  return p;
}

/// Camera translating along +x at `speed` m/s, no rotation.
std::shared_ptr<const Motion> slide(double speed) {
  return std::make_shared<AnalyticMotion>("slide", 0, 1'000'000'000,
                                          [speed](double t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
                                            p = Eigen::Vector3d(speed * t, 0, 0);
                                            q = Eigen::Quaterniond::Identity();
                                          });
}

/// A 240x180 pinhole camera sliding at 0.5 m/s before a 10 m wide wall 2 m away.
FeatureGroundTruth slidingBeforeAWall() {
  Scene scene;
  scene.planes.push_back(frontoParallel("wall", 2.0, 10));
  return FeatureGroundTruth(scene, CameraModel::pinhole(240, 180, 200, 200, 120, 90), slide(0.5));
}

TEST(SampledMotion, InterpolatesBetweenSamplesAndClampsOutside) {
  StampedTrajectory samples(2);
  samples[0].t_ns = 0;
  samples[1].t_ns = 1'000'000;
  samples[1].p_w_c = Eigen::Vector3d(1, 2, 3);
  samples[1].q_w_c = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  const SampledMotion m(samples, "two poses");
  const StampedPose mid = m.pose(250'000);
  EXPECT_LT((mid.p_w_c - Eigen::Vector3d(0.25, 0.5, 0.75)).norm(), 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(mid.q_w_c).angle(), 0.05, 1e-12);
  EXPECT_LT((m.pose(-5).p_w_c).norm(), 1e-15);
  EXPECT_LT((m.pose(2'000'000).p_w_c - samples[1].p_w_c).norm(), 1e-15);
  samples[1].t_ns = -1;
  EXPECT_THROW(SampledMotion(samples, "bad"), std::invalid_argument);
}

TEST(FeatureGroundTruth, PointUnderAPixelMovesAsTheGeometrySays) {
  const FeatureGroundTruth gt = slidingBeforeAWall();
  const FeatureGroundTruth::Anchor a = gt.anchor(0, Eigen::Vector2d(120, 90));
  ASSERT_TRUE(a.valid);
  EXPECT_FALSE(a.depth_edge);
  EXPECT_NEAR(a.depth, 2.0, 1e-12);
  EXPECT_LT((a.p_w - Eigen::Vector3d(0, 0, 2)).norm(), 1e-12);
  // After 0.4 s the camera moved 0.2 m right: the point is 200 * 0.2 / 2 = 20 px to the left.
  const FeatureGroundTruth::Projection p = gt.project(a.p_w, 400'000'000);
  ASSERT_TRUE(p.valid);
  EXPECT_FALSE(p.occluded);
  EXPECT_NEAR(p.pixel.x(), 100.0, 1e-9);
  EXPECT_NEAR(p.pixel.y(), 90.0, 1e-9);
}

TEST(FeatureGroundTruth, AnchorAndProjectionRoundTripThroughTheDistortion) {
  const CameraModel camera = CameraModel::davis240cEcd();
  std::shared_ptr<const Motion> motion = makePresetMotion("6dof", 1.0);
  const FeatureGroundTruth gt(makeBuiltinScene("shapes", *motion, camera, 3), camera, motion);
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(20.3, 15.7), Eigen::Vector2d(120, 90), Eigen::Vector2d(220, 160)}) {
    for (const int64_t t : {int64_t{0}, int64_t{370'000'000}}) {
      const auto a = gt.anchor(t, pixel);
      ASSERT_TRUE(a.valid);
      EXPECT_FALSE(a.depth_edge);
      const auto p = gt.project(a.p_w, t);
      ASSERT_TRUE(p.valid);
      EXPECT_LT((p.pixel - pixel).norm(), 1e-6) << pixel.transpose() << " at " << t;
    }
  }
}

TEST(FeatureGroundTruth, FlagsDepthEdgesAndOcclusion) {
  const CameraModel camera = CameraModel::pinhole(240, 180, 200, 200, 120, 90);
  Scene scene;
  scene.planes.push_back(frontoParallel("wall", 3.0, 10));
  scene.planes.push_back(frontoParallel("card", 1.0, 0.1));  // covers pixels 100..140 at the start
  const FeatureGroundTruth gt(scene, camera, slide(0.5));
  EXPECT_FALSE(gt.anchor(0, Eigen::Vector2d(120, 90)).depth_edge);  // middle of the card
  EXPECT_TRUE(gt.anchor(0, Eigen::Vector2d(140, 90)).depth_edge);   // its right edge
  EXPECT_FALSE(gt.anchor(0, Eigen::Vector2d(170, 90)).depth_edge);  // the wall beside it
  // The camera slides right: the nearer card moves left faster in the image and covers a wall point
  // left of it.
  const auto a = gt.anchor(0, Eigen::Vector2d(95, 90));  // wall, x_w = -0.375 m
  ASSERT_TRUE(a.valid);
  EXPECT_NEAR(a.depth, 3.0, 1e-12);
  // At t = 0.5 s (camera at x = 0.25): the card spans x_c in [-0.35, -0.15] at 1 m, i.e. pixels
  // 50..90; the wall point is at x_c = -0.625 at 3 m, pixel 78.3: behind the card.
  const auto p = gt.project(a.p_w, 500'000'000);
  ASSERT_TRUE(p.valid);
  EXPECT_NEAR(p.pixel.x(), 120 - 200 * 0.625 / 3, 1e-9);
  EXPECT_TRUE(p.occluded);
  EXPECT_FALSE(gt.project(a.p_w, 0).occluded);
  // Background: no plane, no anchor.
  Scene empty;
  const FeatureGroundTruth none(empty, camera, slide(0.5));
  EXPECT_FALSE(none.anchor(0, Eigen::Vector2d(120, 90)).valid);
}

TEST(FeatureAccuracy, CountsErrorsAndLongLivedBadTracks) {
  const FeatureGroundTruth gt = slidingBeforeAWall();
  std::vector<TrackMeasurement> ms;
  // Measurement every 5 ms; track 0 exact, track 1 off by 6 px from 20 ms on for 30 ms (bad, counted),
  // track 2 off by 6 px only at its last two measurements (5 ms: not counted), track 3 has one measurement.
  const auto add = [&](int64_t id, double x0, int64_t t_ns, double offset) {
    const auto a = gt.anchor(0, Eigen::Vector2d(x0, 90));
    const auto p = gt.project(a.p_w, t_ns);
    TrackMeasurement m;
    m.feature_id = id;
    m.t_ns = t_ns;
    m.x = static_cast<float>(p.pixel.x() + offset);
    m.y = static_cast<float>(p.pixel.y());
    ms.push_back(m);
  };
  for (int k = 0; k <= 10; ++k) {
    const int64_t t = k * 5'000'000;
    add(0, 60, t, 0);
    add(1, 120, t, k >= 4 ? 6 : 0);
    add(2, 180, t, k >= 9 ? 6 : 0);
  }
  add(3, 150, 0, 0);
  const FeatureAccuracy r = evaluateFeatureTracks(ms, gt);
  ASSERT_EQ(r.tracks.size(), 4u);
  EXPECT_EQ(r.short_tracks, 1);
  EXPECT_EQ(r.all.tracks, 3);
  EXPECT_EQ(r.all.measurements, 30u);
  EXPECT_EQ(r.all.bad_tracks, 1);
  ASSERT_EQ(r.tracks[1].ages_s.size(), r.tracks[1].errors_px.size());  // one age per error
  for (std::size_t k = 0; k < r.tracks[1].ages_s.size(); ++k)
    EXPECT_NEAR(r.tracks[1].ages_s[k], 0.005 * double(k + 1), 1e-12);  // measurements 1..10 at 5 ms steps
  EXPECT_EQ(r.tracks[1].first_bad_ns, 20'000'000);
  EXPECT_EQ(r.tracks[1].bad_survival_ns, 30'000'000);
  EXPECT_EQ(r.tracks[2].bad_survival_ns, 5'000'000);
  EXPECT_LT(r.tracks[0].max_error_px, 1e-4);  // float positions
  EXPECT_NEAR(r.tracks[1].max_error_px, 6.0, 1e-4);
  EXPECT_LT(r.all.median_px, 1e-4);  // 9 of 30 errors are 6 px
  EXPECT_NEAR(r.all.share_above_bad, 9.0 / 30.0, 1e-12);
  EXPECT_EQ(r.rigid.tracks, 3);
  EXPECT_NE(r.summary().find("surviving > 20 ms: 1"), std::string::npos) << r.summary();
}

TEST(FeatureAccuracy, SignsTheErrorAlongTheMotion) {
  const FeatureGroundTruth gt = slidingBeforeAWall();
  // Two tracks: every measurement after the first 0.3 px behind the image motion (a lag), or 0.2 px
  // across it; the first one is exact (it defines the anchor).
  std::vector<TrackMeasurement> ms;
  const auto add = [&](int64_t id, double x0, int64_t t_ns, double along, double across) {
    const auto a = gt.anchor(0, Eigen::Vector2d(x0, 90));
    const auto p = gt.project(a.p_w, t_ns);
    const Eigen::Vector2d motion =
        (gt.project(a.p_w, t_ns + 1'000'000).pixel - gt.project(a.p_w, t_ns - 1'000'000).pixel).normalized();
    const Eigen::Vector2d q = p.pixel + along * motion + across * Eigen::Vector2d(-motion.y(), motion.x());
    TrackMeasurement m;
    m.feature_id = id;
    m.t_ns = t_ns;
    m.x = static_cast<float>(q.x());
    m.y = static_cast<float>(q.y());
    ms.push_back(m);
  };
  for (int k = 0; k <= 10; ++k) {
    const int64_t t = k * 5'000'000;
    add(0, 80, t, k > 0 ? -0.3 : 0.0, 0.0);
    add(1, 160, t, 0.0, k > 0 ? 0.2 : 0.0);
  }
  const FeatureAccuracy r = evaluateFeatureTracks(ms, gt);
  ASSERT_EQ(r.tracks.size(), 2u);
  ASSERT_EQ(r.tracks[0].along_motion_px.size(), 10u);
  for (double a : r.tracks[0].along_motion_px) EXPECT_NEAR(a, -0.3, 1e-3);
  for (double a : r.tracks[1].along_motion_px) EXPECT_NEAR(a, 0.0, 1e-3);
  // Median of ten -0.3 and ten 0.0: halfway.
  EXPECT_NEAR(r.all.median_along_motion_px, -0.15, 1e-3);
  EXPECT_NE(r.summary().find("median error along the motion -0.150 px"), std::string::npos) << r.summary();
}

TEST(FeatureAccuracy, ATimeOffsetComparesWithTheTruthAtAnotherTime) {
  // An accelerating camera (x = a t^2 / 2, a = 20 m/s^2) before a wall 2 m away; at constant velocity a
  // delay would look like a shifted anchor, with no error at all.
  Scene scene;
  scene.planes.push_back(frontoParallel("wall", 2.0, 10));
  const auto accelerating = std::make_shared<AnalyticMotion>(
      "accelerating", 0, 1'000'000'000, [](double t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
        p = Eigen::Vector3d(10.0 * t * t, 0, 0);
        q = Eigen::Quaterniond::Identity();
      });
  const FeatureGroundTruth gt(scene, CameraModel::pinhole(240, 180, 200, 200, 120, 90), accelerating);
  // A tracker 4 ms late: the measurement stamped t is the true projection at t - 4 ms.
  constexpr int64_t kDelay = 4'000'000;
  const auto a = gt.anchor(0, Eigen::Vector2d(100, 90));
  ASSERT_TRUE(a.valid);
  std::vector<TrackMeasurement> ms;
  for (int k = 0; k <= 20; ++k) {
    TrackMeasurement m;
    m.feature_id = 0;
    m.t_ns = kDelay + k * 5'000'000;
    const Eigen::Vector2d p = gt.project(a.p_w, m.t_ns - kDelay).pixel;
    m.x = static_cast<float>(p.x());
    m.y = static_cast<float>(p.y());
    ms.push_back(m);
  }
  const FeatureAccuracy stamped = evaluateFeatureTracks(ms, gt);
  FeatureAccuracyOptions shifted;
  shifted.time_offset_ns = -kDelay;
  const FeatureAccuracy delayed = evaluateFeatureTracks(ms, gt, shifted);
  ASSERT_EQ(stamped.tracks.size(), 1u);
  ASSERT_EQ(delayed.tracks.size(), 1u);
  // At 0.1 s the image moves at 200 px/s: 4 ms late is about 0.8 px behind.
  EXPECT_GT(stamped.tracks[0].max_error_px, 0.5);
  EXPECT_LT(stamped.all.median_along_motion_px, -0.2);  // behind the motion: a lag
  EXPECT_LT(delayed.tracks[0].max_error_px, 1e-4);
  EXPECT_NEAR(delayed.all.median_along_motion_px, 0.0, 1e-4);
}

TEST(FeatureGroundTruth, RebuildsTheGroundTruthOfASimulatedFolder) {
  TempDir dir;
  SimulationSpec spec;
  spec.scene = "boxes";
  spec.motion = "6dof";
  spec.duration_s = 0.2;
  spec.seed = 7;
  simulateToFolder(spec, dir.file("out"));
  ASSERT_TRUE(isSimulatedDataset(dir.file("out")));
  EXPECT_FALSE(isSimulatedDataset(dir.file("nothing")));
  const FeatureGroundTruth loaded = loadSimulatedGroundTruth(dir.file("out"));
  const CameraModel camera = CameraModel::davis240cEcd();
  std::shared_ptr<const Motion> motion = makeMotion(spec);
  const FeatureGroundTruth exact(makeBuiltinScene("boxes", *motion, camera, 7), camera, motion);
  ASSERT_EQ(loaded.scene().planes.size(), exact.scene().planes.size());
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(40, 40), Eigen::Vector2d(120, 90), Eigen::Vector2d(200, 150)}) {
    const auto a = exact.anchor(13'000'000, pixel);
    const auto b = loaded.anchor(13'000'000, pixel);
    ASSERT_EQ(a.valid, b.valid);
    if (!a.valid) continue;
    EXPECT_LT((a.p_w - b.p_w).norm(), 1e-6);
    const auto pa = exact.project(a.p_w, 187'654'321);
    const auto pb = loaded.project(b.p_w, 187'654'321);
    EXPECT_LT((pa.pixel - pb.pixel).norm(), 1e-3);  // 1 kHz samples of a smooth motion
  }
  std::remove(dir.file("out/sim.yaml").c_str());
  EXPECT_THROW(loadSimulatedGroundTruth(dir.file("out")), InputError);
}

}  // namespace
}  // namespace asynevo::sim
