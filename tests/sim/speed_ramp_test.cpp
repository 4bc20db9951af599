// The speed-ramp preset of the repeated-texture experiment (sim/speed_ramp.hpp).
#include "asynevo/sim/speed_ramp.hpp"

#include <gtest/gtest.h>

#include "asynevo/sim/motion.hpp"

namespace asynevo::sim {
namespace {

TEST(SpeedRamp, WalkingThenSmoothRampThenNineMetresPerSecond) {
  const SpeedRamp ramp;
  EXPECT_DOUBLE_EQ(ramp.speed(0.0), 1.4);
  EXPECT_DOUBLE_EQ(ramp.speed(1.99), 1.4);
  EXPECT_DOUBLE_EQ(ramp.speed(2.75), 5.2);  // smootherstep(1/2) = 1/2: the mean of 1.4 and 9
  EXPECT_DOUBLE_EQ(ramp.speed(3.5), 9.0);
  EXPECT_DOUBLE_EQ(ramp.speed(4.8), 9.0);
  // distance = ∫ speed: 2.8 m walking, 7.8 m in the ramp (its mean speed is 5.2 m/s), then 9 m/s.
  EXPECT_NEAR(ramp.distance(2.0), 2.8, 1e-12);
  EXPECT_NEAR(ramp.distance(3.5), 2.8 + 7.8, 1e-12);
  EXPECT_NEAR(ramp.distance(5.0), 2.8 + 7.8 + 13.5, 1e-12);
  // The closed-form distance is the integral of the speed (midpoint rule, 0.1 ms steps).
  double integral = 0;
  for (double t = 0; t < 3.5; t += 1e-4) integral += ramp.speed(t + 0.5e-4) * 1e-4;
  EXPECT_NEAR(integral, ramp.distance(3.5), 1e-6);
}

TEST(SpeedRamp, PresetMovesAlongXAtTheProfilesSpeedWithoutRotating) {
  const auto motion = makePresetMotion("speed-ramp", 5.0);
  const SpeedRamp ramp;
  for (double t : {0.5, 2.3, 2.75, 3.2, 4.5}) {
    const int64_t t_ns = static_cast<int64_t>(t * 1e9);
    const StampedPose a = motion->pose(t_ns - 500'000), b = motion->pose(t_ns + 500'000);
    const Eigen::Vector3d v = (b.p_w_c - a.p_w_c) / 1e-3;
    EXPECT_NEAR(v.x(), ramp.speed(t), 1e-6) << "t = " << t;
    EXPECT_EQ(v.y(), 0.0);
    EXPECT_EQ(v.z(), 0.0);
    EXPECT_TRUE(a.q_w_c.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs()));
  }
}

}  // namespace
}  // namespace asynevo::sim
