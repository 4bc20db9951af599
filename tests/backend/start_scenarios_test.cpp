// Start scenarios of the initialization issue (docs/method/initialization.md): what must happen when the
// camera does not move at first, on a planar scene, and under a pure rotation.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <random>
#include <vector>

#include "asynevo/backend/init_attempt.hpp"
#include "asynevo/backend/sliding_window_estimator.hpp"
#include "estimator_harness.hpp"

namespace asynevo::backend {
namespace {

using testing::SyntheticScene;

/// The synthetic scene seen by a camera that stands still at the trajectory's first pose for
/// `still_s`, then follows the trajectory: features of 0.4 s, measured every 10 ms with 0.3 px noise.
std::vector<TrackMeasurement> staticThenMoving(const SyntheticScene& scene, double still_s, double moving_s) {
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<TrackMeasurement> out;
  int64_t next_id = 1'000'000;
  const lie::SE3 T_c_w = SyntheticScene::pose(0.0).inverse();
  for (const Eigen::Vector3d& p_w : scene.landmarks) {
    const Eigen::Vector3d p_c = T_c_w * p_w;
    const double u0 = scene.fx * p_c.x() / p_c.z() + scene.cx, v0 = scene.fy * p_c.y() / p_c.z() + scene.cy;
    if (p_c.z() < 0.5 || u0 < 5 || v0 < 5 || u0 > scene.width - 6 || v0 > scene.height - 6) continue;
    for (double start = 0; start < still_s; start += 0.4) {
      const int64_t id = next_id++;
      for (double t = start; t < std::min(start + 0.4, still_s); t += 0.01) {
        TrackMeasurement m;
        m.feature_id = id;
        m.t_ns = std::llround(t * 1e9);
        m.x = static_cast<float>(u0 + noise(rng));
        m.y = static_cast<float>(v0 + noise(rng));
        m.xn = static_cast<float>((m.x - scene.cx) / scene.fx);
        m.yn = static_cast<float>((m.y - scene.cy) / scene.fy);
        out.push_back(m);
      }
    }
  }
  // Then the moving part, shifted by still_s (its ground truth is pose(t − still_s)).
  for (TrackMeasurement m : scene.measurements(moving_s, 0.01, 0.4, 0.3)) {
    m.t_ns += std::llround(still_s * 1e9);
    out.push_back(m);
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; });
  return out;
}

testing::EstimatorRun runScenario(const SyntheticScene& scene, double duration_s, double agreement_deg = 0) {
  const auto ms = scene.measurements(duration_s, 0.01, 0.4, 0.3);
  EstimatorOptions options = testing::syntheticSceneOptions();
  options.config.init_agreement_deg = agreement_deg;
  SlidingWindowEstimator estimator(options);
  return testing::driveEstimator(estimator, ms, duration_s);
}

TEST(StartScenarios, TwoSecondsOfStaticCameraWaitForMotionThenStartWithinHalfASecondOfIt) {
  const SyntheticScene scene(150);
  const double still = 2.0, moving = 2.0;
  const auto ms = staticThenMoving(scene, still, moving);
  SlidingWindowEstimator estimator(testing::syntheticSceneOptions());
  const auto run = testing::driveEstimator(estimator, ms, still + moving);
  ASSERT_TRUE(run.stats.initialized) << run.stats.init_last_failure;
  // No start from a standing camera: the waiting attempts stopped at the motion check.
  EXPECT_GT(run.stats.initialized_at_ns, std::llround(still * 1e9));
  EXPECT_GT(run.stats.init_rejections[static_cast<int>(InitRejection::Motion)], 20u);
  // A scene with its features, waiting for motion, keeps the once-relaxed counts past
  // init_relax_again_after_ms: the second relaxation is for scenes short of features.
  EXPECT_EQ(run.stats.init_relaxed_again, 0u);
  // Started within 0.5 s of the motion's onset, plus one knot interval of measurement lag (measured:
  // 0.25 s after it, 42 attempts stopped at the motion check, ATE 1.05 % of the path).
  EXPECT_LE(run.stats.initialized_at_ns, std::llround((still + 0.55) * 1e9));
  ASSERT_EQ(run.stats.segments.size(), 1u);
  // The estimate from there on follows the shifted ground truth.
  std::vector<Knot> shifted;
  for (Knot k : run.knots) {
    k.t_ns -= std::llround(still * 1e9);
    if (k.t_ns >= 0) shifted.push_back(k);
  }
  ASSERT_GT(shifted.size(), 20u);
  const auto a = testing::accuracy(shifted);
  EXPECT_LT(a.ate_rmse, 0.03 * a.path_length) << a.ate_rmse << " over " << a.path_length;
}

TEST(StartScenarios, EveryFailedAttemptOfAWaitingStartIsLoggedWithItsReason) {
  // The static start above: every failed attempt is in the log, in time order, with the reason its count
  // was added to, the relaxation it was made at and the trajectories it had; init_attempts.txt lists them.
  const SyntheticScene scene(150);
  const auto ms = staticThenMoving(scene, 1.5, 1.0);
  EstimatorOptions options = testing::syntheticSceneOptions();
  SlidingWindowEstimator estimator(options);
  const auto run = testing::driveEstimator(estimator, ms, 2.5);
  ASSERT_TRUE(run.stats.initialized) << run.stats.init_last_failure;
  const auto& log = run.stats.init_attempt_log;
  // Each attempt either failed (and is logged) or started a segment.
  EXPECT_EQ(log.size() + run.stats.segments.size(), run.stats.init_attempts);
  EXPECT_EQ(run.stats.init_attempts_not_logged, 0u);
  std::array<uint64_t, kInitRejections> counted{};
  for (std::size_t i = 0; i < log.size(); ++i) {
    ++counted[static_cast<int>(log[i].rejection)];
    EXPECT_NE(log[i].rejection, InitRejection::None);
    EXPECT_FALSE(log[i].failure.empty());
    EXPECT_LT(log[i].t_ns, run.stats.initialized_at_ns);
    if (i > 0) {
      EXPECT_GT(log[i].t_ns, log[i - 1].t_ns);
      EXPECT_GE(log[i].relaxations, log[i - 1].relaxations);  // one start: the relaxations only grow
    }
  }
  EXPECT_EQ(counted, run.stats.init_rejections);
  EXPECT_EQ(log.back().failure, run.stats.init_last_failure);
  // The standing camera's attempts stop at the motion check, once relaxed after init_relax_after_ms.
  ASSERT_GT(log.size(), 20u);
  EXPECT_EQ(log[10].rejection, InitRejection::Motion);
  EXPECT_GT(log[10].tracks, 0);
  EXPECT_EQ(log.front().relaxations, 0);
  EXPECT_EQ(log.back().relaxations, 1);

  const std::string text = initAttemptsFileText(log, 0);
  EXPECT_EQ(static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')), log.size() + 3);
  EXPECT_NE(text.find("# t_s relaxations tracks rejection failure\n"), std::string::npos);
  EXPECT_NE(text.find(" motion "), std::string::npos);
}

TEST(StartScenarios, TheAttemptsFileSaysHowManyAttemptsItLeftOut) {
  std::vector<InitAttempt> attempts = {{1'500'000'000, 1, 42, InitRejection::Parallax, "median parallax\n2 px"}};
  const std::string text = initAttemptsFileText(attempts, 7);
  EXPECT_NE(text.find("1.500000000 1 42 parallax median parallax 2 px\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# 7 later failed attempts not listed (the log keeps the first 20000)\n"), std::string::npos)
      << text;
}

TEST(StartScenarios, APlanarSceneStartsAndIsTracked) {
  // Every landmark on one plane, 4 m ahead and tilted (a wall or a poster): the essential matrix of a
  // plane is not unique, the five-point RANSAC with the chirality and parallax checks must still pick the
  // motion. The camera follows the synthetic scene's 6-DoF trajectory.
  SyntheticScene scene(0);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> ux(-3.0, 3.5), uy(-2.0, 2.0);
  for (int i = 0; i < 150; ++i) {
    const double x = ux(rng), y = uy(rng);
    scene.landmarks.emplace_back(x, y, 4.0 + 0.3 * x - 0.2 * y);
  }
  const auto run = runScenario(scene, 3.0);
  ASSERT_TRUE(run.stats.initialized) << run.stats.init_last_failure;
  // Measured: a multi-view start at 0.50 s (11 attempts; the two-view start is relaxed at 0.5 s and
  // fails first), ATE 0.57 % of the path.
  EXPECT_LE(run.stats.initialized_at_ns, 550'000'000);
  ASSERT_EQ(run.stats.segments.size(), 1u);
  const auto a = testing::accuracy(run.knots);
  EXPECT_LT(a.ate_rmse, 0.02 * a.path_length) << a.ate_rmse << " over " << a.path_length;
}

TEST(StartScenarios, WithAgreementAStartNeedsTwoAttemptsInARowThatFindTheSameDirection) {
  const SyntheticScene scene(150);
  const auto plain = runScenario(scene, 2.0);
  const auto agreed = runScenario(scene, 2.0, 10.0);
  ASSERT_TRUE(plain.stats.initialized) << plain.stats.init_last_failure;
  ASSERT_TRUE(agreed.stats.initialized) << agreed.stats.init_last_failure;
  // The first motion found waits for the next attempt: at least one knot interval later, and counted.
  EXPECT_GE(agreed.stats.initialized_at_ns, plain.stats.initialized_at_ns + 50'000'000);
  EXPECT_GE(agreed.stats.init_rejections[static_cast<int>(InitRejection::Agreement)], 1u);
  EXPECT_EQ(plain.stats.init_rejections[static_cast<int>(InitRejection::Agreement)], 0u);
  const auto a = testing::accuracy(agreed.knots);
  EXPECT_LT(a.ate_rmse, 0.03 * a.path_length) << a.ate_rmse << " over " << a.path_length;
}

// Under a pure rotation whose rate changes, the relaxed two-view start alone accepts the motion at
// 0.50 s, before the camera translates (the essential matrix's translation is noise, and so is the
// parallax left once its rotation is removed), and the run ends at 5.5 % ATE (docs/method/
// initialization.md, "Limits"). With init_agreement_deg the noise shows: successive attempts find
// directions of travel far apart (up to 108 deg), and the start waits for the translation.
TEST(StartScenarios, PureRotationWaitsForTheTranslationWhenStartsMustAgree) {
  // 1 s of rotation about the camera centre (about 0.5 rad of yaw and 0.2 rad of pitch back and forth),
  // then the same rotation with 0.3 m/s of sideways translation.
  SyntheticScene scene(200);
  const auto truth = [](double t) {
    const Eigen::Vector3d omega(0.3, 0.8, 0.0);
    const double moving = std::max(t - 1.0, 0.0);
    return lie::SE3(lie::so3::exp(omega * std::sin(t) * 0.6), Eigen::Vector3d(0.3 * moving, 0.0, 0.05 * moving));
  };
  scene.trajectory = truth;
  const auto run = runScenario(scene, 3.0, 10.0);
  ASSERT_TRUE(run.stats.initialized) << run.stats.init_last_failure;
  EXPECT_GT(run.stats.initialized_at_ns, 1'000'000'000) << "no start before the camera translates";
  EXPECT_GT(run.stats.init_rejections[static_cast<int>(InitRejection::Agreement)], 5u);
  // Measured: started at 1.65 s, 0.65 s after the translation began (the target is 0.5 s: the
  // 0.3 m/s sideways step needs that long to give an agreeing direction under the rotation), 14 attempts
  // rejected for disagreeing, ATE 0.79 % of the path.
  EXPECT_LE(run.stats.initialized_at_ns, 1'700'000'000) << "a start within 0.7 s of the translation";
  const auto a = testing::accuracy(run.knots, truth);
  EXPECT_LT(a.ate_rmse, 0.03 * a.path_length) << a.ate_rmse << " over " << a.path_length;
}

testing::EstimatorRun runRetriangulating(const SyntheticScene& scene, bool retriangulate) {
  const auto ms = scene.measurements(3.0, 0.01, 0.4, 0.3);
  EstimatorOptions options = testing::syntheticSceneOptions();
  options.config.init_retriangulate = retriangulate;
  options.config.init_relax_after_ms = 500;  // the wait these scenarios were measured with
  SlidingWindowEstimator estimator(options);
  return testing::driveEstimator(estimator, ms, 3.0);
}

// With init_retriangulate, the trajectories that failed to triangulate against the start's
// constant-twist knots are tried again once the first solve has fitted the knots to the landmarks
// (docs/method/initialization.md, "First knots").
TEST(StartScenarios, TrajectoriesThatFailedAgainstTheStartsKnotsAreTriedAgainAfterItsSolve) {
  // The rotation rate changes within the start's window (yaw 0.3 rad at 3 rad/s, accelerating sideways
  // from rest): the constant-twist knots are degrees off and many trajectories miss the 3 px bound.
  SyntheticScene scene(150);
  scene.trajectory = [](double t) {
    return lie::SE3(lie::so3::exp(Eigen::Vector3d(0.09 * std::sin(3 * t), 0.3 * std::sin(3 * t), 0.0)),
                    Eigen::Vector3d(0.3 * t * t, 0.0, 0.1 * t));
  };
  const auto plain = runRetriangulating(scene, false);
  const auto again = runRetriangulating(scene, true);
  ASSERT_TRUE(plain.stats.initialized && again.stats.initialized);
  ASSERT_FALSE(plain.records.empty() || again.records.empty());
  EXPECT_EQ(again.stats.initialized_at_ns, plain.stats.initialized_at_ns);
  EXPECT_EQ(plain.stats.init_retriangulations, 0u);
  EXPECT_EQ(again.stats.init_retriangulations, again.stats.segments.size());
  // Measured: 44 landmarks after the start's solve without, 66 with.
  EXPECT_GE(again.records.front().landmarks, plain.records.front().landmarks + 10);
}

TEST(StartScenarios, RetriangulatingChangesNothingWhereTheStartsKnotsAreRight) {
  // The synthetic scene's gentle motion: every trajectory that can triangulate does so against the
  // constant-twist knots, so the second pass finds none and the run is the same bit for bit.
  const SyntheticScene scene(150);
  const auto plain = runRetriangulating(scene, false);
  const auto again = runRetriangulating(scene, true);
  ASSERT_TRUE(again.stats.initialized);
  EXPECT_EQ(again.stats.init_retriangulations, 0u);
  ASSERT_EQ(again.knots.size(), plain.knots.size());
  for (std::size_t i = 0; i < plain.knots.size(); ++i) {
    EXPECT_EQ(again.knots[i].t_ns, plain.knots[i].t_ns);
    EXPECT_EQ(again.knots[i].pose, plain.knots[i].pose) << "knot " << i;
  }
}

// With init_two_view_landmarks, a two-view start whose trajectories miss the constant-twist knots
// triangulates the trajectories seen at its two times from those two views alone, and its first solve
// fits the knots to them (docs/method/initialization.md, "First knots").
TEST(StartScenarios, AStartWithTooFewLandmarksAgainstItsKnotsTriangulatesFromItsTwoViews) {
  // The rotation rate changes within the start's window (yaw 0.4 rad at 6 rad/s, accelerating sideways
  // from rest): the first two-view start's knots triangulate too few landmarks.
  SyntheticScene scene(150);
  scene.trajectory = [](double t) {
    return lie::SE3(lie::so3::exp(Eigen::Vector3d(0.12 * std::sin(6 * t), 0.4 * std::sin(6 * t), 0.0)),
                    Eigen::Vector3d(0.3 * t * t, 0.0, 0.1 * t));
  };
  const auto ms = scene.measurements(3.0, 0.01, 0.4, 0.3);
  const auto runWith = [&](bool two_view_landmarks) {
    EstimatorOptions options = testing::syntheticSceneOptions();
    options.config.init_two_view_landmarks = two_view_landmarks;
    options.config.init_relax_after_ms = 500;  // the wait this scenario was measured with
    // ... and the window's triangulation: with solved_then_all (the default since 2026-12-07) the window
    // recovers more slowly from this start, ATE 6.2 % of the path against 2.4 %
    // (docs/results/window_landmarks.md).
    options.config.triangulation_views = "all";
    SlidingWindowEstimator estimator(options);
    return testing::driveEstimator(estimator, ms, 3.0);
  };
  const auto plain = runWith(false);
  const auto two_view = runWith(true);
  ASSERT_TRUE(plain.stats.initialized && two_view.stats.initialized);
  const auto landmark_rejections = [](const testing::EstimatorRun& run) {
    return run.stats.init_rejections[static_cast<int>(InitRejection::Landmarks)];
  };
  // Measured: without, one attempt rejected for landmarks and a start at 0.557 s (27 landmarks); with,
  // the start one attempt earlier, at 0.507 s, with 75 landmarks after its solve; ATE 2.50 and 2.38 %.
  EXPECT_GE(landmark_rejections(plain), 1u);
  EXPECT_EQ(plain.stats.init_two_view_landmark_starts, 0u);
  EXPECT_GE(two_view.stats.init_two_view_landmark_starts, 1u);
  EXPECT_LT(landmark_rejections(two_view), landmark_rejections(plain));
  EXPECT_LE(two_view.stats.initialized_at_ns, plain.stats.initialized_at_ns - 50'000'000);
  ASSERT_FALSE(two_view.records.empty());
  EXPECT_GT(two_view.records.front().landmarks, plain.records.front().landmarks);
  const auto a = testing::accuracy(two_view.knots, scene.trajectory);
  EXPECT_LT(a.ate_rmse, 0.04 * a.path_length) << a.ate_rmse << " over " << a.path_length;
}

TEST(StartScenarios, ASceneWithTooFewFeaturesForTheRelaxedCountsStartsOnceRelaxedAgain) {
  // Sixteen scene points: 8-14 features seen at two times, fewer than the once-relaxed counts need (15).
  const SyntheticScene scene(16);
  const double duration = 3.0;
  const auto ms = scene.measurements(duration, 0.01, 0.8, 0.3);
  const auto runWith = [&](double again_ms) {
    EstimatorOptions options = testing::syntheticSceneOptions();
    options.config.init_relax_again_after_ms = again_ms;
    SlidingWindowEstimator estimator(options);
    return testing::driveEstimator(estimator, ms, duration);
  };
  const auto once = runWith(0);
  const auto twice = runWith(1000);
  EXPECT_FALSE(once.stats.initialized) << once.stats.init_last_failure;
  EXPECT_GT(once.stats.init_rejections[static_cast<int>(InitRejection::Features)], 0u);
  ASSERT_TRUE(twice.stats.initialized) << twice.stats.init_last_failure;
  EXPECT_EQ(once.stats.init_relaxed_again, 0u);
  EXPECT_EQ(twice.stats.init_relaxed_again, 1u);
  // Not before the second relaxation, and soon after it (measured: 1.33 s, ATE 1.4 % of the path).
  EXPECT_GE(twice.stats.initialized_at_ns, 1'000'000'000);
  EXPECT_LE(twice.stats.initialized_at_ns, 1'500'000'000);
  const auto a = testing::accuracy(twice.knots);
  EXPECT_LT(a.ate_rmse, 0.05 * a.path_length) << a.ate_rmse << " over " << a.path_length;
}

}  // namespace
}  // namespace asynevo::backend
