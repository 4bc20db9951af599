// The direction audit of a young segment: the window's motion between two times against its
// depth-reversed alternative, on the bearings of the trajectories seen at both times.
#include "asynevo/backend/direction_audit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "asynevo/lie/se3.hpp"

namespace asynevo::backend {
namespace {

constexpr double kFocal = 300.0;
constexpr int64_t kMs = 1'000'000;

double angleDeg(const lie::Vec3& u, const lie::Vec3& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / M_PI;
}

/// Camera poses along a straight path: at s (0..1) the camera is at s·travel with a rotation of s·turn.
lie::SE3 poseAt(double s, const lie::Vec3& travel, const lie::Vec3& turn) {
  return lie::SE3(lie::so3::exp(s * turn), s * travel);
}

/// Knots at 0, 100 and 200 ms along poseAt.
Trajectory window(const lie::Vec3& travel, const lie::Vec3& turn) {
  Trajectory w;
  for (int k = 0; k <= 2; ++k) w.add(k * 100 * kMs, poseAt(0.5 * k, travel, turn), lie::Vec6::Zero());
  return w;
}

/// `n` points 2–6 m ahead in a narrow view (±0.25 rad) of the first camera, each observed every 20 ms
/// over 0..200 ms by a camera that really moves along poseAt(travel, turn), with 0.3 px of noise.
TrackMap tracksOf(const lie::Vec3& travel, const lie::Vec3& turn, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(-0.25, 0.25), depth(2.0, 6.0);
  std::normal_distribution<double> noise(0.0, 0.3 / kFocal);
  TrackMap tracks;
  for (int i = 0; i < n; ++i) {
    const double z = depth(rng);
    const lie::Vec3 p_w(std::tan(angle(rng)) * z, std::tan(angle(rng)) * z, z);
    FeatureTrack& track = tracks[i];
    track.id = i;
    for (int k = 0; k <= 10; ++k) {
      const lie::Vec3 p_c = poseAt(0.1 * k, travel, turn).inverse() * p_w;
      track.observations.push_back(
          {k * 20 * kMs, Eigen::Vector2d(p_c.x() / p_c.z() + noise(rng), p_c.y() / p_c.z() + noise(rng))});
    }
  }
  return tracks;
}

const lie::Vec3 kTravel(0.15, 0.015, 0.02);  // mostly sideways, 0.15 m in 200 ms
const lie::Vec3 kTurn(0.0, 0.03, 0.0);

/// x_b = R_b_a x_a + t_b_a of the true motion from 0 to 200 ms, normalized.
lie::Vec3 trueDirection() {
  return (poseAt(1.0, kTravel, kTurn).inverse() * poseAt(0.0, kTravel, kTurn)).translation().normalized();
}

TEST(DirectionAudit, AWindowTravellingTheTrueWayKeepsItsDirection) {
  const TrackMap tracks = tracksOf(kTravel, kTurn, 40, 1);
  const auto check = auditDirection(window(kTravel, kTurn), tracks, 0, 200 * kMs, kFocal, 1.0, 5.0, 15);
  ASSERT_TRUE(check.has_value());
  EXPECT_STREQ(check->method, "audit");
  EXPECT_EQ(check->features, 40);
  EXPECT_LT(angleDeg(check->t_b_a, trueDirection()), 1.0);
  // Either no alternative, or one clearly dearer than the window's own motion.
  if (check->found) {
    EXPECT_GT(check->reversed_cost, 1.5 * check->cost);
  }
}

TEST(DirectionAudit, AWindowTravellingInReverseFindsTheTrueDirectionCheaper) {
  // The same images, but the window's knots travel the other way (as a depth-reversed start does).
  const TrackMap tracks = tracksOf(kTravel, kTurn, 40, 2);
  const auto check = auditDirection(window(-kTravel, kTurn), tracks, 0, 200 * kMs, kFocal, 1.0, 5.0, 15);
  ASSERT_TRUE(check.has_value());
  EXPECT_GT(angleDeg(check->t_b_a, trueDirection()), 170.0);  // the window's direction, as audited
  ASSERT_TRUE(check->found);
  EXPECT_LT(check->reversed_cost, (1.0 - 0.33) * check->cost);  // votes at the default margin
  EXPECT_LT(angleDeg(check->reversed_t_b_a, trueDirection()), 15.0);
}

TEST(DirectionAudit, NoAuditOfARotationOrOfTooFewTrajectoriesOrOutsideTheWindow) {
  // A rotation with 1 mm of travel: about 1 px of parallax, below the 5 px asked for.
  const lie::Vec3 creep(0.001, 0, 0), turn(0.0, 0.2, 0.0);
  EXPECT_FALSE(auditDirection(window(creep, turn), tracksOf(creep, turn, 40, 3), 0, 200 * kMs, kFocal, 1.0, 5.0, 15));
  // The same rotation is audited once no parallax is asked for.
  EXPECT_TRUE(auditDirection(window(creep, turn), tracksOf(creep, turn, 40, 3), 0, 200 * kMs, kFocal, 1.0, 0.0, 15));
  // Fewer trajectories than asked for.
  EXPECT_FALSE(auditDirection(window(kTravel, kTurn), tracksOf(kTravel, kTurn, 14, 4), 0, 200 * kMs, kFocal, 1.0,
                              5.0, 15));
  EXPECT_TRUE(auditDirection(window(kTravel, kTurn), tracksOf(kTravel, kTurn, 15, 4), 0, 200 * kMs, kFocal, 1.0, 5.0,
                             15));
  // A time the window or the trajectories do not cover.
  EXPECT_FALSE(auditDirection(window(kTravel, kTurn), tracksOf(kTravel, kTurn, 40, 5), 0, 300 * kMs, kFocal, 1.0,
                              5.0, 15));
}

}  // namespace
}  // namespace asynevo::backend
