// Tracking accuracy on sequences of the project simulator against exact feature ground truth
// (sim/feature_ground_truth.hpp): issue 3's simulated-sequence targets, median error <= 1 px and no track
// with error > 5 px surviving more than 20 ms. Short sequences (0.6 s, ~1 s CPU each to simulate).
// Figures for longer sequences and for the scenes where the targets are missed: docs/frontend.md.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "../../bench/frontend/frontend_run.hpp"
#include "../../bench/frontend/sim_sequence.hpp"
#include "asynevo/frontend/frontend.hpp"

namespace asynevo::frontend {
namespace {

sim::FeatureAccuracy run(const std::string& scene, const std::string& motion, double seconds, uint64_t seed,
                         const FrontendConfig& config = {}, FrontendStats* stats = nullptr,
                         std::vector<TrackMeasurement>* measurements = nullptr, CameraModel* camera = nullptr) {
  const bench::SimSequence s = bench::simulateSequence(scene, motion, seconds, seed);
  const bench::FrontendRun fe = bench::runFrontend(config, s.events, s.camera);
  const sim::FeatureAccuracy r = sim::evaluateFeatureTracks(fe.out.measurements, *s.ground_truth);
  if (measurements != nullptr) *measurements = fe.out.measurements;
  if (camera != nullptr) *camera = s.camera;
  std::printf("%s (%.1f s, seed %llu):\n%s", s.name.c_str(), seconds, static_cast<unsigned long long>(seed),
              r.summary().c_str());
  if (stats != nullptr) *stats = fe.stats;
  return r;
}

uint64_t neighbourDrops(const FrontendStats& stats) {
  return stats.features_dropped[static_cast<int>(DropReason::kNeighbour)];
}

TEST(SimulatedAccuracy, ShapesSixDofMeetsTheTargets) {
  const sim::FeatureAccuracy r = run("shapes", "6dof", 0.6, 1);
  ASSERT_GE(r.all.tracks, 30);
  EXPECT_LE(r.all.median_px, 1.0);
  EXPECT_EQ(r.all.bad_tracks, 0) << "tracks with error > 5 px surviving > 20 ms";
  EXPECT_EQ(r.depth_edge_tracks, 0);  // one plane: no depth discontinuity
}

TEST(SimulatedAccuracy, CheckerboardSixDofMeetsTheTargets) {
  const sim::FeatureAccuracy r = run("checkerboard", "6dof", 0.6, 1);
  ASSERT_GE(r.all.tracks, 30);
  EXPECT_LE(r.all.median_px, 1.0);
  EXPECT_EQ(r.all.bad_tracks, 0) << "tracks with error > 5 px surviving > 20 ms";
}

// Boxes: cubes before a wall with a smooth multi-scale noise texture ("blobs"). The median target is met
// since the drift and rotation tests; the bad-track target is still MISSED (docs/frontend.md): on the soft
// blob contours the event pattern itself depends on the motion direction, so a tracker can slide with a
// window that still matches its first template. This test bounds today's figures (0.75 px median, 11 bad
// tracks of 188; before the drift test 1.09 px and 19 of 90) so that they do not get worse.
TEST(SimulatedAccuracy, BoxesSixDofMeetsTheMedianAndBoundsTheBadTracks) {
  const sim::FeatureAccuracy r = run("boxes", "6dof", 0.6, 1);
  ASSERT_GE(r.all.tracks, 100);
  EXPECT_LE(r.all.median_px, 1.0);
  EXPECT_LE(r.rigid.median_px, 0.9);
  EXPECT_LE(r.all.bad_tracks, r.all.tracks / 10) << "tracks with error > 5 px surviving > 20 ms";
  EXPECT_GT(r.depth_edge_tracks, 0);  // silhouettes against the wall are detected as such
}

// Poster: a photograph-like texture. Median target met; bad tracks bounded (1 of 119 measured; 2 s:
// 5 of 252, before the drift test 24 of 151).
TEST(SimulatedAccuracy, PosterSixDofMeetsTheMedianAndBoundsTheBadTracks) {
  const sim::FeatureAccuracy r = run("poster", "6dof", 0.6, 1);
  ASSERT_GE(r.all.tracks, 60);
  EXPECT_LE(r.all.median_px, 1.0);
  EXPECT_LE(r.all.bad_tracks, 3) << "tracks with error > 5 px surviving > 20 ms";
}

// The continuous sub-pixel fit (subpixel_method template_fit): the same tracks, measured closer to the
// truth than by the parabola, most of all young ones.
TEST(SimulatedAccuracy, TheSubpixelFitLowersThePosterMedian) {
  FrontendConfig fit;
  fit.subpixel_method = "template_fit";
  const sim::FeatureAccuracy with = run("poster", "6dof", 0.6, 1, fit);
  const sim::FeatureAccuracy without = run("poster", "6dof", 0.6, 1);
  EXPECT_EQ(with.all.tracks, without.all.tracks);  // the trackers are the same
  std::printf("median %.3f px with the fit, %.3f px with the parabola\n", with.all.median_px, without.all.median_px);
  EXPECT_LT(with.all.median_px, 0.95 * without.all.median_px);
}

// Rectified tracking (docs/method/frontend.md, "Tracking frame"): the trackers run on the undistorted
// pinhole image, and each measurement's sensor pixel and normalized coordinates are the same point
// through the camera model. The tracks meet the same targets as on the raw pixels.
TEST(SimulatedAccuracy, RectifiedTrackingMeetsTheTargetsAndMeasuresConsistently) {
  FrontendConfig config;
  config.rectified_tracking = true;
  std::vector<TrackMeasurement> measurements;
  CameraModel camera = CameraModel::davis240cEcd();
  const sim::FeatureAccuracy r = run("shapes", "6dof", 0.6, 1, config, nullptr, &measurements, &camera);
  ASSERT_GE(r.all.tracks, 30);
  EXPECT_LE(r.all.median_px, 1.0);
  EXPECT_EQ(r.all.bad_tracks, 0) << "tracks with error > 5 px surviving > 20 ms";
  ASSERT_FALSE(measurements.empty());
  double worst = 0;
  for (const TrackMeasurement& m : measurements) {
    const Eigen::Vector2d ray = *camera.unproject(Eigen::Vector2d(m.x, m.y));
    worst = std::max(worst, std::hypot(ray.x() - m.xn, ray.y() - m.yn) * camera.fx());
  }
  EXPECT_LT(worst, 0.01) << "px between a measurement's pixel and its normalized coordinates";
}

// Sub-pixel measurements (docs/frontend.md): the same tracks, measured between the grid positions.
// On 2 s of poster the median falls from 0.61 to 0.47 px; on 0.6 s it must at least fall.
TEST(SimulatedAccuracy, SubpixelMeasurementsLowerThePosterMedian) {
  FrontendConfig on;
  on.subpixel_measurements = true;
  FrontendConfig off;
  off.subpixel_measurements = false;
  const sim::FeatureAccuracy with = run("poster", "6dof", 0.6, 1, on);
  const sim::FeatureAccuracy without = run("poster", "6dof", 0.6, 1, off);
  EXPECT_EQ(with.all.tracks, without.all.tracks);  // the trackers are the same
  EXPECT_LT(with.all.median_px, 0.9 * without.all.median_px);
}

// Neighbour-motion test (max_neighbour_disagreement_px, off by default; docs/frontend.md): a feature whose
// displacement over the last 60 ms departs by more than 4 px from the median of its nearest features'
// is dropped. Measured on 0.6 s of poster: bad tracks 3 -> 0 (2 s: 7 -> 0); boxes 12 -> 7 (2 s: 47 -> 22).
FrontendConfig neighbourConfig(double limit_px) {
  FrontendConfig c;
  c.max_neighbour_disagreement_px = limit_px;
  c.neighbour_window_ms = 60;
  return c;
}

TEST(SimulatedAccuracy, NeighbourMotionTestLowersThePosterBadTracks) {
  FrontendStats on_stats, off_stats;
  const sim::FeatureAccuracy on = run("poster", "6dof", 0.6, 1, neighbourConfig(4.0), &on_stats);
  const sim::FeatureAccuracy off = run("poster", "6dof", 0.6, 1, neighbourConfig(0.0), &off_stats);
  EXPECT_GE(off.all.bad_tracks, 1);  // what the test is for
  // With the default drift test (max_drift_px 4; it removed every bad track here at 2 px) the neighbour
  // test halves them: 4 -> 2 tracks with error > 5 px surviving > 20 ms.
  EXPECT_LT(on.all.bad_tracks, off.all.bad_tracks);
  EXPECT_LE(on.all.bad_tracks, 2) << "tracks with error > 5 px surviving > 20 ms";
  EXPECT_LE(on.all.median_px, off.all.median_px);
  EXPECT_GT(neighbourDrops(on_stats), 0u);
  EXPECT_EQ(neighbourDrops(off_stats), 0u);
  EXPECT_EQ(off_stats.neighbour_tests, 0u);  // off means not evaluated at all
  // Churn stays small: at most 15 % more features, lifetimes not shorter by more than 10 %.
  EXPECT_LE(on_stats.features_created, off_stats.features_created * 115 / 100);
  EXPECT_GE(on.all.lifetime_median_s, 0.9 * off.all.lifetime_median_s);
}

TEST(SimulatedAccuracy, NeighbourMotionTestLowersTheBoxesBadTracks) {
  const sim::FeatureAccuracy on = run("boxes", "6dof", 0.6, 1, neighbourConfig(4.0));
  const sim::FeatureAccuracy off = run("boxes", "6dof", 0.6, 1, neighbourConfig(0.0));
  EXPECT_LT(on.all.bad_tracks, off.all.bad_tracks);
  EXPECT_LE(on.all.bad_tracks, 8);
}

// neighbour_disagreement_fraction widens the limit by a share of the neighbours' own displacement: on the
// same stream it drops fewer features than the fixed limit, and still some.
TEST(SimulatedAccuracy, NeighbourMotionLimitThatGrowsWithTheMotionDropsFewer) {
  FrontendStats fixed_stats, relative_stats;
  FrontendConfig relative = neighbourConfig(4.0);
  relative.neighbour_disagreement_fraction = 0.5;
  run("boxes", "6dof", 0.6, 1, neighbourConfig(4.0), &fixed_stats);
  run("boxes", "6dof", 0.6, 1, relative, &relative_stats);
  EXPECT_GT(relative_stats.neighbour_tests, 0u);
  EXPECT_GT(neighbourDrops(relative_stats), 0u);
  EXPECT_LT(neighbourDrops(relative_stats), neighbourDrops(fixed_stats));
}

// A roll about the optical axis moves neighbours apart in proportion to their distance: at 2 rad/s two
// features 50 px apart part by 6 px in the test's 60 ms. The translation model then ends correct tracks;
// the similarity model (neighbour_motion_model) carries each neighbour's displacement through the
// neighbours' common rotation and keeps them, and so does `either` (dropped only when both disagree),
// without letting bad tracks through.
sim::FeatureAccuracy runRoll(const bench::SimSequence& s, const std::string& model, FrontendStats& stats) {
  FrontendConfig config;
  config.neighbour_motion_model = model;
  const bench::FrontendRun fe = bench::runFrontend(config, s.events, s.camera);
  stats = fe.stats;
  const sim::FeatureAccuracy r = sim::evaluateFeatureTracks(fe.out.measurements, *s.ground_truth);
  std::printf("%s, %s model: %llu neighbour drops\n%s", s.name.c_str(), model.c_str(),
              static_cast<unsigned long long>(neighbourDrops(stats)), r.summary().c_str());
  return r;
}

TEST(SimulatedAccuracy, UnderARollTheSimilarityModelKeepsTheNeighbours) {
  const double rate = 2.0;  // rad/s about the optical axis, with a slow sideways drift
  auto roll = std::make_shared<sim::AnalyticMotion>(
      "roll", 0, 400'000'000, [rate](double t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
        p = Eigen::Vector3d(0.05 * t, 0.0, 0.0);
        q = Eigen::Quaterniond(Eigen::AngleAxisd(rate * t, Eigen::Vector3d::UnitZ()));
      });
  const bench::SimSequence s = bench::simulateSequence("checkerboard", roll, "roll", 1);
  FrontendStats translation_stats;
  const sim::FeatureAccuracy translation = runRoll(s, "translation", translation_stats);
  EXPECT_GE(neighbourDrops(translation_stats), 10u);  // what the model is for
  for (const std::string model : {"similarity", "either"}) {
    FrontendStats stats;
    const sim::FeatureAccuracy r = runRoll(s, model, stats);
    EXPECT_GT(stats.neighbour_tests, 1000u) << model;  // the test runs
    EXPECT_LE(neighbourDrops(stats) * 4, neighbourDrops(translation_stats)) << model;
    EXPECT_GT(r.all.lifetime_median_s, 2 * translation.all.lifetime_median_s) << model;
    // Measured: 0 (translation), 0 (similarity), 1 track above 5 px for 22 ms (either), of 109-238.
    EXPECT_LE(r.all.bad_tracks, translation.all.bad_tracks + 1) << model;
    EXPECT_LE(r.all.median_px, 1.0) << model;
  }
}

// `either` consults the similarity only when it moves the feature by neighbour_similarity_min_px (1 px)
// relative to its neighbours. Under a sideways translation, where neighbours part only by depth, the
// similarity fitted to a few neighbours is noise: gated, `either` ends as many features as the
// translation model, with as many bad tracks; ungated it lets some go on (measured: 23 drops and 8 bad
// tracks, against 17 and 9 ungated).
TEST(SimulatedAccuracy, UnderATranslationTheGatedEitherModelIsTheTranslationModel) {
  FrontendConfig translation, gated, ungated;
  gated.neighbour_motion_model = "either";
  ungated.neighbour_motion_model = "either";
  ungated.neighbour_similarity_min_px = 0;
  FrontendStats t_stats, g_stats, u_stats;
  const sim::FeatureAccuracy t = run("boxes", "translation", 0.6, 1, translation, &t_stats);
  const sim::FeatureAccuracy g = run("boxes", "translation", 0.6, 1, gated, &g_stats);
  run("boxes", "translation", 0.6, 1, ungated, &u_stats);
  EXPECT_GE(neighbourDrops(t_stats), 10u);
  EXPECT_EQ(neighbourDrops(g_stats), neighbourDrops(t_stats));
  EXPECT_EQ(g.all.bad_tracks, t.all.bad_tracks);
  EXPECT_LT(neighbourDrops(u_stats), neighbourDrops(t_stats));
}

// With a limit no displacement reaches, the test runs (features are evaluated) but changes nothing.
TEST(SimulatedAccuracy, NeighbourMotionTestIsInertBelowItsLimit) {
  FrontendStats inert_stats;
  const sim::FeatureAccuracy inert = run("poster", "6dof", 0.6, 1, neighbourConfig(1000.0), &inert_stats);
  const sim::FeatureAccuracy off = run("poster", "6dof", 0.6, 1, neighbourConfig(0.0));
  EXPECT_GT(inert_stats.neighbour_tests, 1000u);
  EXPECT_EQ(neighbourDrops(inert_stats), 0u);
  EXPECT_EQ(inert.all.tracks, off.all.tracks);
  EXPECT_EQ(inert.all.median_px, off.all.median_px);
  EXPECT_EQ(inert.all.bad_tracks, off.all.bad_tracks);
}

}  // namespace
}  // namespace asynevo::frontend
