// Two-view initialization: the parallax that counts is what is left once the rotation is removed.
#include "asynevo/backend/initializer.hpp"

#include <gtest/gtest.h>

#include <random>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {
namespace {

constexpr double kFocal = 200.0;
constexpr int64_t kTa = 100'000'000, kTb = 300'000'000;

/// Tracks of `n` points 3–6 m in front of the camera, each measured at t_a and t_b, seen from the
/// identity pose at t_a and from `T_w_b` at t_b, with `noise_px` Gaussian noise.
TrackMap twoViewTracks(const lie::SE3& T_w_b, int n, double noise_px, unsigned seed = 7, double depth_scale = 1.0,
                       int first_id = 0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-1.5, 1.5), uy(-1.0, 1.0), uz(3.0, 6.0);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  auto noise = [&](std::mt19937& g) { return noise_px / kFocal * gaussian(g); };
  TrackMap tracks;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p_w = depth_scale * Eigen::Vector3d(ux(rng), uy(rng), uz(rng));
    const Eigen::Vector3d p_b = T_w_b.inverse() * p_w;
    FeatureTrack& track = tracks[first_id + i];
    track.id = first_id + i;
    track.observations.push_back({kTa, Eigen::Vector2d(p_w.x() / p_w.z() + noise(rng), p_w.y() / p_w.z() + noise(rng))});
    track.observations.push_back({kTb, Eigen::Vector2d(p_b.x() / p_b.z() + noise(rng), p_b.y() / p_b.z() + noise(rng))});
  }
  return tracks;
}

BackendConfig initConfig() {
  BackendConfig config;
  config.init_window_ms = 200;  // one span: t_a .. t_b
  config.init_min_parallax_px = 10;
  config.init_min_features = 30;
  config.init_min_inliers = 25;
  return config;
}

TEST(InitializeTwoView, RejectsARotationThatMovesTheImageALotWithLittleBaseline) {
  // 8 degrees about the vertical axis (~28 px of image motion) and a 3 cm baseline (~1-2 px of parallax).
  const lie::SE3 T_w_b(lie::so3::exp(Eigen::Vector3d(0.0, 8.0 * M_PI / 180.0, 0.0)), Eigen::Vector3d(0.03, 0.0, 0.01));
  // Noise-free, so the five-point pose itself is good and only the parallax test can say no.
  const InitResult result = initializeTwoView(twoViewTracks(T_w_b, 80, 0.0), kTa, kTb, kFocal, initConfig());
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.failure.find("once the rotation"), std::string::npos) << result.failure;
}

TEST(InitializeTwoView, AcceptsATranslationAndRecoversItsDirection) {
  // 0.6 m sideways and forward with a small rotation: ~20-40 px of parallax at 3-6 m.
  const Eigen::Vector3d baseline(0.6, 0.05, 0.2);
  const lie::SE3 T_w_b(lie::so3::exp(Eigen::Vector3d(0.01, -0.03, 0.02)), baseline);
  // 0.1 px of noise: sideways translation and rotation about the vertical axis are nearly ambiguous in
  // two narrow views, so more noise would tilt the pose (the bundle adjustment after it refines).
  const InitResult result = initializeTwoView(twoViewTracks(T_w_b, 80, 0.1), kTa, kTb, kFocal, initConfig());
  ASSERT_TRUE(result.ok) << result.failure;
  EXPECT_EQ(result.t_a_ns, kTa);
  EXPECT_GT(result.parallax_px, 10.0);
  EXPECT_LT(result.parallax_px, 50.0);
  EXPECT_GT(result.T_a_b.translation().normalized().dot(baseline.normalized()), 0.99);
  EXPECT_LT(lie::so3::log(result.T_a_b.rotation().transpose() * T_w_b.rotation()).norm(), 0.02);
}

TEST(InitializeTwoView, RequiresTheConfiguredParallax) {
  const lie::SE3 T_w_b(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.6, 0.05, 0.2));
  BackendConfig config = initConfig();
  config.init_min_parallax_px = 60;  // more than this baseline gives, raw or with the rotation removed
  const InitResult result = initializeTwoView(twoViewTracks(T_w_b, 80, 0.1), kTa, kTb, kFocal, config);
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.failure.find("(need 60.0)"), std::string::npos) << result.failure;
}

/// Camera at time t: moving sideways and forward at constant velocity, turning slowly (identity at kTa).
lie::SE3 movingCamera(int64_t t_ns) {
  const double s = 1e-9 * static_cast<double>(t_ns - kTa);
  return lie::SE3(lie::so3::exp(Eigen::Vector3d(0.0, 0.02 * s, 0.01 * s)), Eigen::Vector3d(1.5 * s, 0.1 * s, 0.3 * s));
}

/// Adds to `tracks` one track per point, measured every 10 ms from `first` to `last` by movingCamera.
void addTracks(TrackMap& tracks, const std::vector<Eigen::Vector3d>& points_w, int64_t first, int64_t last) {
  for (const Eigen::Vector3d& p_w : points_w) {
    const int64_t id = static_cast<int64_t>(tracks.size());
    FeatureTrack& track = tracks[id];
    track.id = id;
    for (int64_t t = first; t <= last; t += 10'000'000) {
      const Eigen::Vector3d p_c = movingCamera(t).inverse() * p_w;
      track.observations.push_back({t, p_c.head<2>() / p_c.z()});
    }
  }
}

std::vector<Eigen::Vector3d> randomPoints(int n, double depth_scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-1.5, 1.5), uy(-1.0, 1.0), uz(3.0, 6.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) points.push_back(depth_scale * Eigen::Vector3d(ux(rng), uy(rng), uz(rng)));
  return points;
}

double score(const InitResult& r) { return r.parallax_px * std::sqrt(static_cast<double>(r.inliers)); }

TEST(InitializeTwoView, CountsFarPointsAsInliersAndKeepsTheirRotation) {
  // 20 points at 3-6 m make the parallax; 40 points 300-600 m away (more than 50 baselines, which
  // cv::recoverPose would drop as outliers) only pin the rotation. Together they pass 25 inliers.
  TrackMap tracks;
  addTracks(tracks, randomPoints(20, 1.0, 7), kTa, kTb);
  addTracks(tracks, randomPoints(40, 100.0, 8), kTa, kTb);
  BackendConfig config = initConfig();
  config.init_min_parallax_px = 0.05;  // the median point is far: its parallax is tiny
  const InitResult result = initializeTwoView(tracks, kTa, kTb, kFocal, config);
  ASSERT_TRUE(result.ok) << result.failure;
  EXPECT_EQ(result.inliers, 60);
  const lie::SE3 T_a_b = movingCamera(result.t_a_ns).inverse() * movingCamera(result.t_b_ns);
  EXPECT_GT(result.T_a_b.translation().normalized().dot(T_a_b.translation().normalized()), 0.99);
  EXPECT_LT(lie::so3::log(result.T_a_b.rotation().transpose() * T_a_b.rotation()).norm(), 1e-3);
}

TEST(InitializeTwoView, ChoosesTheSpanWithTheBestScore) {
  // Every span passes; the score (parallax x sqrt(inliers)) of the chosen one is at least that of each
  // candidate span on its own. Half of the features start 50 ms late, so the full span, with the
  // most parallax but only 30 features, loses to a shorter span that sees all 60.
  BackendConfig config = initConfig();
  config.init_window_ms = 300;
  config.init_min_parallax_px = 3;
  const int64_t t_b = kTa + 300'000'000;
  TrackMap tracks;
  addTracks(tracks, randomPoints(30, 1.0, 3), kTa, t_b);
  addTracks(tracks, randomPoints(30, 1.0, 4), kTa + 50'000'000, t_b);
  const InitResult best = initializeTwoView(tracks, kTa, t_b, kFocal, config);
  ASSERT_TRUE(best.ok) << best.failure;
  int passing = 0;
  for (int part = kInitSpans; part >= 1; --part) {
    const int64_t t_a = t_b - 300'000'000LL * part / kInitSpans;
    const InitResult r = initializeTwoViewSpan(tracks, t_a, t_b, kFocal, config);
    if (!r.ok) continue;
    ++passing;
    EXPECT_GE(score(best), score(r)) << "span from " << t_a;
  }
  EXPECT_GE(passing, 3);
  EXPECT_GT(best.t_a_ns, kTa);
  EXPECT_EQ(best.features, 60);
}

}  // namespace
}  // namespace asynevo::backend
