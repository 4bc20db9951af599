#include "asynevo/frontend/rotation_check.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "asynevo/core/config/frontend_config.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/event_reader.hpp"

namespace asynevo::frontend {
namespace {

// Tracks of static points seen by a camera rotating at constant angular velocity (exact bearings).
std::vector<TrackMeasurement> rotatingTracks(const Eigen::Vector3d& omega, double noise_px, double fx,
                                             int seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::normal_distribution<double> n(0.0, noise_px / fx);
  std::vector<TrackMeasurement> out;
  for (int j = 0; j < 20; ++j) {
    const Eigen::Vector3d p0(u(rng), u(rng), 1.0);  // bearing at t = 0
    const double start = 0.01 * (j % 5);
    for (int k = 0; k < 12; ++k) {
      const double t = start + 0.005 * k;
      const Eigen::Vector3d p =
          Eigen::AngleAxisd(omega.norm() * t, omega.normalized()).toRotationMatrix().transpose() * p0;
      TrackMeasurement m;
      m.feature_id = j;
      m.t_ns = static_cast<int64_t>(std::llround(t * 1e9));
      m.xn = static_cast<float>(p.x() / p.z() + n(rng));
      m.yn = static_cast<float>(p.y() / p.z() + n(rng));
      out.push_back(m);
    }
  }
  return out;
}

TEST(RotationCheck, RecoversTheAngularVelocityOfExactTracks) {
  const Eigen::Vector3d omega(0.3, -1.2, 0.5);
  const auto tracks = rotatingTracks(omega, 0.0, 200.0, 1);
  const RotationFitResult r = fitCommonRotation(tracks, 200.0, 200.0);
  EXPECT_LT((r.omega - omega).norm(), 1e-3) << r.omega.transpose();
  EXPECT_LT(r.median_px, 0.01);
  EXPECT_EQ(r.tracks_used, 20);
  EXPECT_EQ(r.measurements, 240);
  EXPECT_NEAR(r.lifetime_max_s, 0.055, 1e-9);
}

TEST(RotationCheck, OutlierTracksDoNotBiasTheFitAndShowInTheResiduals) {
  const Eigen::Vector3d omega(0.0, 0.6, -0.1);
  auto tracks = rotatingTracks(omega, 0.3, 200.0, 2);
  // Two drifting tracks: 100 px/s along x on top of the rotation.
  for (auto& m : tracks)
    if (m.feature_id < 2) m.xn += static_cast<float>(0.5 * m.t_ns * 1e-9);
  const RotationFitResult r = fitCommonRotation(tracks, 200.0, 200.0);
  EXPECT_LT((r.omega - omega).norm(), 0.05) << r.omega.transpose();
  EXPECT_LT(r.median_px, 0.6);
  EXPECT_GT(r.share_above_3px, 0.0);
}

TEST(RotationCheck, TooFewTracksIsAnError) {
  auto tracks = rotatingTracks(Eigen::Vector3d(0, 1, 0), 0.0, 200.0, 3);
  tracks.resize(12);  // one track
  EXPECT_THROW(fitCommonRotation(tracks, 200.0, 200.0), std::invalid_argument);
}

struct SliceResult {
  RotationFitResult fit;
  FrontendStats stats;
};

SliceResult runSlice(const std::string& name, const FrontendConfig& config) {
  const std::string dir = std::string(ASYNEVO_SOURCE_DIR) + "/tests/data/ecd/" + name;
  const std::vector<Event> events = readAllEvents(dir + "/events.txt");
  const CameraModel camera = readEcdCalibration(dir + "/calib.txt");
  Frontend fe(config, camera.width(), camera.height(), camera.undistortionTable<float>());
  MeasurementCollector out;
  for (const Event& e : events) fe.process(e, out);
  fe.finish(out);
  return {fitCommonRotation(out.measurements, camera.fx(), camera.fy()), fe.stats()};
}

// Issue 3 accuracy target on the real ECD shapes_rotation slice (hand-held, nearly pure rotation):
// residuals to one common rotation, median <= 1.0 px and 90th percentile <= 2.5 px, with the default
// configuration; the fitted angular velocity agrees with the gyro reading (motion.txt: -0.061 0.575 -0.142).
TEST(RotationCheck, ShapesRotationSliceMeetsTheAccuracyTarget) {
  const SliceResult r = runSlice("shapes_rotation", FrontendConfig{});
  EXPECT_LE(r.fit.median_px, 1.0);
  EXPECT_LE(r.fit.p90_px, 2.5);
  EXPECT_GE(r.fit.tracks_used, 5);
  EXPECT_GE(r.fit.measurements, 40);
  EXPECT_LT((r.fit.omega - Eigen::Vector3d(-0.06067522, 0.5754361, -0.14236432)).norm(), 0.2)
      << r.fit.omega.transpose();
}

// dynamic_rotation (21 ms): too short for throttled measurements; every state change is recorded.
TEST(RotationCheck, DynamicRotationSliceIsConsistentWithOneRotation) {
  FrontendConfig config;
  config.min_dt_ms = 0;
  const SliceResult r = runSlice("dynamic_rotation", config);
  EXPECT_LE(r.fit.median_px, 1.0);
  EXPECT_LE(r.fit.p90_px, 2.5);
  EXPECT_GE(r.fit.tracks_used, 5);
  EXPECT_NEAR(r.fit.omega.y(), 1.782, 0.6);  // gyro: -0.013 1.782 0.121 (|w| grows quickly here)
}

}  // namespace
}  // namespace asynevo::frontend
