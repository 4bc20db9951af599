// The start's first knots: the constant-twist knots, and their rotations refitted to the tracks.
#include "asynevo/backend/start_trajectory.hpp"

#include <gtest/gtest.h>

#include "asynevo/core/time.hpp"
#include "window_tracks.hpp"

namespace asynevo::backend {
namespace {

constexpr int64_t kKnotDt = 50'000'000;

/// Hand-held motion: 0.4 m/s sideways (world frame), a yaw rate growing from 0.6 to 1.6 rad/s over the
/// window (34 to 92 deg/s) with some pitch and roll.
lie::SE3 accelerating(double t) {
  const Eigen::Vector3d omega0(0.05, 0.6, 0.05), alpha(0.3, 2.0, -0.2);
  return lie::SE3(lie::so3::exp(omega0 * t + 0.5 * alpha * t * t), Eigen::Vector3d(0.4, 0.05, 0.1) * t);
}

/// The start's motion as an initializer would report it: the true relative pose over the window,
/// translation scaled to 1.
InitResult startFrom(const PoseAt& pose) {
  InitResult motion;
  motion.ok = true;
  motion.t_a_ns = kT0;
  motion.t_b_ns = kT1;
  const lie::SE3 T = pose(0.0).inverse() * pose(0.5);
  motion.T_a_b = lie::SE3(T.rotation(), T.translation().normalized());
  return motion;
}

/// The largest rotation error of the knots against the truth (deg).
double maxRotationErrorDeg(const Trajectory& trajectory, const PoseAt& pose) {
  double worst = 0;
  for (const auto& [t, knot] : trajectory.knots()) {
    const lie::Mat3 R = pose(durationSeconds(kT0, t)).rotation();
    worst = std::max(worst, lie::so3::log(R.transpose() * knot.T_w_c().rotation()).norm() * 180.0 / M_PI);
  }
  return worst;
}

TEST(ConstantTwistTrajectory, KnotsOnTheGridAtTheStartsScale) {
  const PoseAt pose = constantTwist(Eigen::Vector3d(0.6, 0.0, 0.2), Eigen::Vector3d(0.0, 0.3, 0.0));
  const Trajectory trajectory = constantTwistTrajectory(startFrom(pose), kT1 + kKnotDt, kKnotDt);
  ASSERT_EQ(trajectory.size(), 12u);  // 0, 50, ..., 550 ms
  EXPECT_EQ(trajectory.oldestTime(), kT0);
  EXPECT_EQ(trajectory.newestTime(), kT1 + kKnotDt);
  // Mean speed over the span is 1 map unit per second: the chord of 0.5 s is 0.5 units long here,
  // where the motion is a constant twist (the chord of the helix, as its twist is the start's).
  const lie::SE3 T_b = trajectory.find(kT1)->T_w_c();
  EXPECT_NEAR(T_b.translation().norm(), 0.5, 1e-9);
  EXPECT_LT(maxRotationErrorDeg(trajectory, pose), 1e-6);
}

TEST(StartTravelDirection, IsTheBodyFrameVelocityWhateverTheSpanAndRotation) {
  // A constant twist: 0.6 m/s along x and 0.2 along z in the body frame while yawing at 0.3 rad/s
  // (17 deg/s); over the span the chord's direction turns with the rotation, the twist's does not.
  const Eigen::Vector3d v(0.6, 0.0, 0.2);
  const PoseAt pose = constantTwist(v, Eigen::Vector3d(0.0, 0.3, 0.0));
  const InitResult motion = startFrom(pose);
  EXPECT_LT((startTravelDirection(motion) - v.normalized()).norm(), 1e-9);
  // A shorter span of the same motion, later in time: the same direction.
  InitResult later = motion;
  later.t_a_ns = kT0 + 200'000'000;
  const lie::SE3 T = pose(0.2).inverse() * pose(0.5);
  later.T_a_b = lie::SE3(T.rotation(), T.translation().normalized());
  EXPECT_LT(travelAngleDeg(motion, later), 1e-6);
  // A start whose direction is 30 deg off (turned about y).
  InitResult off = motion;
  const lie::SE3 T_off = constantTwist(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitY()) * v,
                                       Eigen::Vector3d(0.0, 0.3, 0.0))(0.5);
  off.T_a_b = lie::SE3(T_off.rotation(), T_off.translation().normalized());
  EXPECT_NEAR(travelAngleDeg(motion, off), 30.0, 1e-6);
}

TEST(RefineStartRotations, FollowsARotationRateThatChangesInTheWindow) {
  const PoseAt pose = accelerating;
  const TrackMap tracks = tracksOf(pose, 120, 0.2, 0.3, 11, 4.0);
  Trajectory trajectory = constantTwistTrajectory(startFrom(pose), kT1, kKnotDt);
  const double before = maxRotationErrorDeg(trajectory, pose);
  EXPECT_GT(before, 1.5) << "the constant twist must be off for this test to mean anything";

  const RotationRefinement r = refineStartRotations(trajectory, tracks, 1.0 / kFocal);
  EXPECT_EQ(r.intervals, 10);
  EXPECT_GE(r.refined, 9);  // the last knot, at the tracks' ends, may be seen by too few
  // What is left comes from the held positions: the constant twist's path is a helix, the truth a line.
  const double after = maxRotationErrorDeg(trajectory, pose);
  EXPECT_LT(after, 0.7) << "before " << before << " deg";
  EXPECT_LT(after, before / 5);
  EXPECT_GT(r.max_change_deg, 1.0);
  // Positions are held: the start's baseline, hence its scale, does not change.
  const Trajectory constant = constantTwistTrajectory(startFrom(pose), kT1, kKnotDt);
  for (const auto& [t, knot] : trajectory.knots()) {
    EXPECT_LT((knot.T_w_c().translation() - constant.find(t)->T_w_c().translation()).norm(), 1e-12);
  }
  // Velocities are the twists between neighbour knots.
  const auto first = trajectory.knots().begin();
  const lie::Vec6 w = lie::se3::log(first->second.T_w_c().inverse() * std::next(first)->second.T_w_c()) / 0.05;
  EXPECT_LT((first->second.twist() - w).norm(), 1e-9);
}

TEST(RefineStartRotations, LeavesAConstantTwistAsItIs) {
  const PoseAt pose = constantTwist(Eigen::Vector3d(0.5, 0.1, 0.2), Eigen::Vector3d(0.1, 0.8, 0.0));
  const TrackMap tracks = tracksOf(pose, 120, 0.2, 0.3, 11, 4.0);
  Trajectory trajectory = constantTwistTrajectory(startFrom(pose), kT1, kKnotDt);
  const RotationRefinement r = refineStartRotations(trajectory, tracks, 1.0 / kFocal);
  EXPECT_GE(r.refined, 9);
  EXPECT_LT(r.max_change_deg, 0.3);
  EXPECT_LT(maxRotationErrorDeg(trajectory, pose), 0.3);
}

TEST(RefineStartRotations, IntervalsWithTooFewFeaturesKeepTheirRotation) {
  const PoseAt pose = accelerating;
  // 5 points: no knot is seen by kMinRefitFeatures features.
  const TrackMap tracks = tracksOf(pose, 5, 0.5, 0.0, 11, 1.0);
  Trajectory trajectory = constantTwistTrajectory(startFrom(pose), kT1, kKnotDt);
  const Trajectory constant = trajectory;
  const RotationRefinement r = refineStartRotations(trajectory, tracks, 1.0 / kFocal);
  EXPECT_EQ(r.intervals, 10);
  EXPECT_EQ(r.refined, 0);
  EXPECT_LT(r.max_change_deg, 1e-9);
  for (const auto& [t, knot] : trajectory.knots()) {
    EXPECT_LT((knot.T_w_c().matrix() - constant.find(t)->T_w_c().matrix()).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace asynevo::backend
